#ifndef PARKSLAM_SCENE_SCENE_H_
#define PARKSLAM_SCENE_SCENE_H_

// A randomized scene around the car, for training and hard evaluation of
// perception on top views (the paper's detectors are learned, section
// III-A; they need labelled images by the thousand, and the images must be
// as varied as real lots). Everything is in the vehicle frame (x forward,
// y left, z up, origin at the rear axle on the ground), in metres: the car
// stands still at the origin and the lot is drawn around it.
//
// A scene is a plain description: the slot rows with their marking points
// and slots (the labels), every painted stroke and text, the floor's
// material, decals and dirt, the solid objects (parked cars, pillars, walls,
// people, cones), the light, and each camera's look. SampleScene draws one
// from a seed; the painter and the renderer turn it into pixels.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace parkslam::scene {

// BGR in 0..255 (OpenCV's order), linear light before the cameras.
using Colour = Eigen::Vector3f;

// A marking point (ps2.0 / DMPR-PS): where a separating line meets the
// entrance line, on both centre lines.
struct MarkingPoint {
  Eigen::Vector2d p_vehicle = Eigen::Vector2d::Zero();
  Eigen::Vector2d direction =
      Eigen::Vector2d::UnitX();  // unit, along the separating line, into the slot
  bool is_t = true;              // T: the entrance line goes on both sides; L: one side only
};

enum class SlotKind : std::uint8_t { kPerpendicular, kParallel, kAngled };

// One slot by its entrance line: marking points a and b (indices into
// Scene::marks); walking from a to b the slot lies to the left in the
// vehicle frame (right on the top view's screen).
struct Slot {
  int a = 0, b = 0;
  SlotKind kind = SlotKind::kPerpendicular;
  double angle_deg = 90.0;  // between separating lines and entrance line
  double depth_m = 5.0;     // along the separating lines
  std::string id;           // painted text; empty: none
  bool id_legible = false;  // painted, readable and not hidden by wear
};

enum class PaintKind : std::uint8_t { kWhite, kYellow, kRed, kBlue, kBlack };

// A painted straight stroke on the floor.
struct Stroke {
  Eigen::Vector2d a = Eigen::Vector2d::Zero(), b = Eigen::Vector2d::Zero();
  double width_m = 0.15;
  PaintKind paint = PaintKind::kWhite;
  double opacity = 1.0;    // 0: gone, 1: fresh paint
  double wear = 0.0;       // share of the stroke flaked off in patches
  bool slot_line = false;  // part of a slot's lines (where labels live)
};

// Text painted on the floor: a slot's ID or other floor text.
struct FloorText {
  std::string text;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  Eigen::Vector2d right =
      Eigen::Vector2d::UnitX();  // unit reading direction; up is its left normal
  double height_m = 0.5;
  int font = 0;                // index into the font book (modulo its size)
  bool seven_segment = false;  // the default lot's digits instead of `font`
  bool bold = false;
  bool stencil = false;  // the bridges of a stencil cut through the strokes
  double stretch = 1.0;  // width over the font's natural width (condensed < 1)
  PaintKind paint = PaintKind::kWhite;
  double opacity = 1.0;
  double wear = 0.0;
  int slot = -1;  // the slot it names, or -1
};

enum class DecalKind : std::uint8_t {
  kArrow,
  kZebra,
  kSpeedBump,
  kManhole,
  kGrate,
  kWheelStop,
  kOilStain,
  kTyreMark,
  kPuddle,
  kDirt,
  kPatch,
  kCrack,
  kLeaves
};

// Anything else on the floor, in a box centred at `center`, its length
// along `yaw_rad`.
struct Decal {
  DecalKind kind = DecalKind::kOilStain;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
  double length_m = 1.0, width_m = 1.0;
  double strength = 1.0;  // 0..1: how much it shows
  std::uint64_t seed = 0;
};

enum class FloorMaterial : std::uint8_t { kConcrete, kEpoxy, kAsphalt, kBricks, kTiles };

struct Floor {
  FloorMaterial material = FloorMaterial::kConcrete;
  Colour base{128, 128, 128};
  Colour joint{80, 80, 80};  // bricks' and tiles' joints
  double texture = 1.0;      // amplitude of the material's own texture
  double blotches = 1.0;     // amplitude of metre-scale unevenness
  double unit_m = 0.2;       // brick length or tile edge
  double pattern_yaw_rad = 0.0;
  bool herringbone = false;
  double gloss = 0.0;  // 0: matt; 1: lamps mirror in it (epoxy)
  // Outdoor edge: grass, gravel or a kerb beyond a line parallel to the rows.
  bool verge = false;
  Eigen::Vector2d verge_point = Eigen::Vector2d::Zero();
  Eigen::Vector2d verge_normal = Eigen::Vector2d::UnitY();  // points into the verge
  bool verge_gravel = false;
  bool kerb = true;
};

enum class SolidShape : std::uint8_t { kBox, kCylinder, kCone };
enum class SolidMaterial : std::uint8_t { kPaint, kGlass, kTyre, kMatt, kSkin };

// A solid standing on the floor: an oriented box (its vertical edges
// rounded when corner_radius_m > 0, as a car's plan is), a vertical
// cylinder or a cone (radius half_x at z0, zero at z1).
struct Solid {
  SolidShape shape = SolidShape::kBox;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
  double half_x = 0.5, half_y = 0.5;  // box half extents; cylinder and cone: half_x the radius
  double corner_radius_m = 0.0;       // box: radius of its rounded vertical edges
  double z0 = 0.0, z1 = 1.0;
  Colour colour{128, 128, 128};
  SolidMaterial material = SolidMaterial::kMatt;
  bool stripes = false;  // hazard stripes (pillars) or a cone's white bands
  bool casts_shadow = true;
};

struct Lighting {
  bool outdoor = false;
  double gain = 1.0;     // overall light
  Colour tint{1, 1, 1};  // colour of the light (per channel factor)
  // Indoor: ceiling lamps on a grid, pools of light under them.
  double lamp_spacing_m = 6.0;
  Eigen::Vector2d lamp_offset = Eigen::Vector2d::Zero();
  double lamp_height_m = 2.8;
  // The lamp grid's axes turned by this from the scene's (a lot seen from
  // a turned car); the lamps' tubes run along its first axis.
  double lamp_grid_yaw_rad = 0.0;
  double pools = 0.3;   // 0: even; 1: strong pools, dark between
  double patchy = 0.2;  // amplitude of metre-scale light variation
  bool night = false;   // a few warm lamps, dark elsewhere
  // Backlight: a bright side (an open end, a gate) in direction backlight_dir.
  double backlight = 0.0;
  Eigen::Vector2d backlight_dir = Eigen::Vector2d::UnitX();
  // Outdoor: the sun, its hard shadows and the sky.
  double sun_azimuth_rad = 0.0, sun_elevation_rad = 0.8;
  double shadow_depth = 0.5;  // 0: no shadows; 1: black shadows
  int trees = 0;              // dappled shadows of trees
  std::uint64_t seed = 0;
};

// How one camera sees (the four fisheyes differ: visible seams).
struct CameraLook {
  double exposure = 1.0;
  Colour white_balance{1, 1, 1};
  double vignetting = 0.3;
  double noise_sigma = 3.0;  // grey levels
  double motion_blur_px = 0.0;
  double motion_angle_rad = 0.0;
  double defocus_px = 0.0;    // Gaussian sigma
  double sensor_scale = 1.0;  // < 1: a coarser sensor (the image resampled down and up)
  int dirt_spots = 0;         // a dirty lens
  double glare = 0.0;         // the sun or a lamp shining into the lens
  int jpeg_quality = 95;      // 100: no compression
  // Colour blotches a few pixels across (grey levels, the standard
  // deviation of the blue and red deviations), as cheap sensors' chroma
  // noise and demosaicing leave them; 0: none.
  double chroma_noise = 0.0;
  std::uint64_t seed = 0;
};

// An AprilTag (tag36h11) on a wall or pillar, facing normal_yaw_rad, for
// the front camera (paper III-B). size_m is the edge of its black square;
// a white margin of one cell lies round it (tag_texture.h).
struct WallTag {
  int tag_id = 0;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double normal_yaw_rad = 0.0;
  double z_center_m = 1.35;
  double size_m = 0.5;
};

struct Scene {
  std::uint64_t seed = 0;
  std::vector<MarkingPoint> marks;
  std::vector<Slot> slots;
  std::vector<Stroke> strokes;
  std::vector<FloorText> texts;
  std::vector<Decal> decals;
  std::vector<Solid> solids;
  std::vector<WallTag> tags;
  Floor floor;
  Lighting light;
  std::vector<CameraLook> cameras;  // in the order of the rig's fusion cameras
  CameraLook front_camera;          // the monocular front camera
  int fusion_calibration = 0;       // 0: exact; k > 0: the k-th perturbed calibration
  int fusion_seams = 0;             // which of the renderer's seam layouts the unit draws
                                    // (its straight-seam layouts follow the others)
  int top_view_jpeg_quality = 90;   // the fused view as saved
  double top_view_sharpen = 0.0;    // unsharp mask some surround-view units apply
  bool fusion_nearest = false;      // the unit's lookup takes the nearest camera pixel
  double saturation = 1.0;          // colour saturation of the whole unit
};

struct SceneSamplerOptions {
  int fisheye_cameras = 4;
  int perturbed_calibrations = 8;  // fusion_calibration is drawn from 0..this
  int seam_layouts = 3;            // fusion_seams is drawn from 0..this - 1
  double outdoor_probability = 0.4;
  double parked_car_probability_max = 0.8;  // per slot, drawn per row up to this
  // Ego vehicle, for keeping the lot's solids off the car.
  double ego_length_m = 4.7, ego_width_m = 1.85, ego_rear_overhang_m = 1.0;
  // Share of the rows whose IDs are digits in the default lot's
  // seven-segment face (font/digit_font.h). Taken from the row's font
  // draw, so that 0 leaves every scene exactly as it was.
  double seven_segment_share = 0.0;
  // Share of scenes whose surround-view unit has a coarse sensor (its
  // fisheyes resampled down and up: far lines smear), and share whose
  // fusion takes the nearest camera pixel instead of interpolating
  // (camera::FusionLookup: sharp, jagged lines). Drawn last among the
  // cameras' looks, so that a nearest share of 0 leaves every scene as it
  // was.
  double coarse_sensor_share = 0.6;
  double nearest_lookup_share = 0.0;
  // Share of units whose seams are straight rays from the footprint's
  // corners (camera::SeamStyle::kFootprintRays, as ps2.0's views show),
  // drawn among the renderer's ray_seam_layouts straight layouts. Drawn
  // last of all, so that a share of 0 leaves every scene as it was.
  double ray_seam_share = 0.0;
  int ray_seam_layouts = 3;
  // Share of units whose cameras show chroma noise (CameraLook::
  // chroma_noise, up to chroma_noise_max grey levels). Drawn after the
  // seams, so that a share of 0 leaves every scene as it was.
  double chroma_noise_share = 0.0;
  double chroma_noise_max = 7.0;

  bool IsValid(std::string* error) const;
};

// A random scene, deterministic by seed.
Scene SampleScene(std::uint64_t seed, const SceneSamplerOptions& options = {});

// A look without a layout: the floor, the light and the cameras drawn as
// SampleScene draws them, from their own streams of `seed` (a lot's look,
// lot_scene.h).
struct Look {
  Floor floor;
  Lighting light;
  std::vector<CameraLook> cameras;
  CameraLook front_camera;
};
Look SampleLook(std::uint64_t seed, bool outdoor, const SceneSamplerOptions& options = {});

// A parked car (body, cabin, tyres) at `center`, its length along yaw_rad.
void AddParkedCar(std::uint64_t seed, const Eigen::Vector2d& center, double yaw_rad, Scene* scene);

// The paint's colour before light (BGR).
Colour PaintColour(PaintKind paint);

}  // namespace parkslam::scene

#endif  // PARKSLAM_SCENE_SCENE_H_
