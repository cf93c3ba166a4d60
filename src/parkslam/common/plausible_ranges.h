#ifndef PARKSLAM_COMMON_PLAUSIBLE_RANGES_H_
#define PARKSLAM_COMMON_PLAUSIBLE_RANGES_H_

// The plausible ranges of every physical quantity the project reads: sensor
// streams, observations, maps, trajectories, camera rigs, scenarios and
// command-line values. A value beyond them is not a parking lot, a car or a
// camera but a broken or misread file; refusing it where it is read names
// the file and field, where letting it through would surface as infinities
// or gigabyte allocations far from its cause. The limits are generous: the
// project's own outputs, the shipped worlds and the real sample data lie far
// inside. docs/plausible_ranges.md tables them with the fields they bound.
//
// Units are in the names; a limit without one is dimensionless.

#include <cstddef>

namespace parkslam {

// ---------------------------------------------------------------------------
// Sensor streams (dataset sensors/*.csv), in magnitude.

// Wheel speed: 216 km/h, far beyond any car in a parking lot, yet still a car.
inline constexpr double kMaxWheelSpeed_mps = 60.0;
// Steering-wheel angle: almost 5 turns; real cars lock at about 1.5 to 2.
inline constexpr double kMaxSteeringWheelAngle_rad = 30.0;
// Yaw rate: over 3 turns a second; a car turns at most about 1 rad/s.
inline constexpr double kMaxYawRate_radps = 20.0;
// Any angle in radians (IMU heading, yaws, bearings, --init): unwrapped
// angles are fine, and a double still resolves 2e-12 rad at 1e4.
inline constexpr double kMaxAngle_rad = 1e4;

// ---------------------------------------------------------------------------
// Positions and their uncertainty.

// |x|, |y| of a map-frame point (maps, trajectories, scenario geometry,
// --init): 100 km around the origin holds any site's local frame.
inline constexpr double kMaxCoordinate_m = 1e5;
// |x|, |y| and range of what the car's sensors report in the vehicle frame
// (slot corners, tags): a top view spans 10 m, tags are used to 20 m.
inline constexpr double kMaxObservationRange_m = 100.0;
// Standard deviation of a position (slot corners; the square root of a tag
// covariance's diagonal): beyond 10 m it says nothing in a lot of 2.5 m slots.
inline constexpr double kMaxPositionSigma_m = 10.0;
// Standard deviation of an angle: beyond half a turn it says nothing.
inline constexpr double kMaxAngleSigma_rad = 3.14159265358979323846;
// Side of an AprilTag: one on a wall or pillar under a 2 to 4 m ceiling;
// the project's tags are 0.488 m.
inline constexpr double kMaxTagSize_m = 5.0;
// Tag IDs: the tag36h11 family, the one the front end detects, holds IDs
// 0 to 586.
inline constexpr int kTagIdCount = 587;
// A slot's area: the smallest slot (kMinSlotSide_m square) has 2.25 m²; a
// slot whose corners enclose less than this is four points on a line or on
// top of each other, not a slot.
inline constexpr double kMinSlotArea_m2 = 0.5;

// ---------------------------------------------------------------------------
// Images and cameras.

// Image sides and area: what any command decodes (64 million pixels, 16384 a
// side); a 960 x 640 fisheye and a 600 x 600 top view are far below.
inline constexpr int kMinImageSide_px = 16;
inline constexpr int kMaxImageSide_px = 16384;
inline constexpr long long kMaxImagePixels = 64LL * 1000 * 1000;
// |x|, |y| of a labelled pixel: a mark may lie outside its image, but not by
// more than the largest image.
inline constexpr double kMaxPixelCoordinate_px = 2.0 * kMaxImageSide_px;
// Focal length: 1 px sees everything in a few pixels; at 1e5 px even the
// largest image spans only 9 degrees (the project's cameras: 180 to 640 px).
inline constexpr double kMinFocalLength_px = 1.0;
inline constexpr double kMaxFocalLength_px = 1e5;
// How far outside the image the principal point may lie, as a share of the
// image's width or height; calibrations put it within a few % of the centre.
inline constexpr double kPrincipalPointMargin = 0.5;
// |k| of a distortion coefficient (Kannala-Brandt k1..k4, or k1, k2, p1, p2):
// real lenses stay within about 1 (the real sample: 0.04), wide pinholes
// reach a few.
inline constexpr double kMaxDistortionCoefficient = 100.0;
// |x|, |y| of a camera in the vehicle frame: on the vehicle, and an
// articulated bus is 18 m long.
inline constexpr double kMaxCameraOffset_m = 20.0;
// Height z of a camera: above the ground it looks at, below a parking
// hall's ceiling.
inline constexpr double kMaxCameraHeight_m = 5.0;
// An angle in degrees in a configuration (camera yaw, pitch and roll, row
// directions, slot label angles): one turn either way.
inline constexpr double kMaxAngle_deg = 360.0;
// scale_xy of a homography camera (the undistorted view's focal length over
// the calibrated one): the real sample uses 0.4 to 1.
inline constexpr double kMinUndistortScale = 0.01;
inline constexpr double kMaxUndistortScale = 100.0;
// |det H| / |H|^3 (Frobenius) of a ground-plane homography: below, it is
// singular and maps the image onto a line; the real sample's are above 1e-10.
inline constexpr double kMinHomographyDeterminant = 1e-15;

// ---------------------------------------------------------------------------
// The vehicle (scenario `vehicle`).

// Wheelbase: a city car is 2.3 m, a bus 6 m.
inline constexpr double kMinWheelbase_m = 0.5;
inline constexpr double kMaxWheelbase_m = 10.0;
// Steering-wheel angle over road-wheel angle: cars use 12 to 20.
inline constexpr double kMinSteeringRatio = 1.0;
inline constexpr double kMaxSteeringRatio = 50.0;
// Largest road-wheel angle: cars lock at 30 to 40 degrees (1.2 rad is 69).
inline constexpr double kMinRoadWheelAngle_rad = 0.05;
inline constexpr double kMaxRoadWheelAngle_rad = 1.2;
// Road-wheel rate: a lock-to-lock turn in 0.1 s at most.
inline constexpr double kMaxRoadWheelRate_radps = 10.0;
// Length and width of the vehicle: an articulated bus, a truck.
inline constexpr double kMaxVehicleLength_m = 20.0;
inline constexpr double kMaxVehicleWidth_m = 5.0;

// ---------------------------------------------------------------------------
// Scenarios: the lot, the drive, the simulated sensors.

// Side of the hall, and any other length of the lot or the drive (corridor,
// tag spacing, pillars, lookahead): the largest garages are a few hundred
// metres a side.
inline constexpr double kMinHallSide_m = 10.0;
inline constexpr double kMaxHallSide_m = 1000.0;
// Width of the entrance corridor: one lane to a wide ramp.
inline constexpr double kMinCorridorWidth_m = 2.0;
inline constexpr double kMaxCorridorWidth_m = 20.0;
// Width and depth of a slot (and the depths the slot sensor guesses): a
// motorbike bay to a bus bay.
inline constexpr double kMinSlotSide_m = 1.5;
inline constexpr double kMaxSlotSide_m = 10.0;
// Angle between separating and entrance lines of an angled slot.
inline constexpr double kMinSlotAngle_deg = 30.0;
inline constexpr double kMaxSlotAngle_deg = 150.0;
// Cruise speed of a human drive through a lot.
inline constexpr double kMinDriveSpeed_kmh = 0.5;
inline constexpr double kMaxDriveSpeed_kmh = 40.0;
// Acceleration and braking: about 1 g, more than tyres give.
inline constexpr double kMaxAcceleration_mps2 = 10.0;
// Rates of the odometry sensors and of the simulated drive's samples.
inline constexpr double kMinSensorRate_hz = 1.0;
inline constexpr double kMaxSensorRate_hz = 1000.0;
inline constexpr double kMinRouteSampleRate_hz = 20.0;
// Frame rate of the cameras behind slot and tag detections.
inline constexpr double kMaxCameraRate_hz = 100.0;
// Side of the simulated top view (10 m as ps2.0); its centre lies within
// half of this of the rear axle, so what it sees stays within
// kMaxObservationRange_m.
inline constexpr double kMinTopViewSide_m = 2.0;
inline constexpr double kMaxTopViewSide_m = 50.0;
// Relative noise (a scale error's sigma; a sigma's growth per metre of
// distance): 100 %.
inline constexpr double kMaxRelativeSigma = 1.0;

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_PLAUSIBLE_RANGES_H_
