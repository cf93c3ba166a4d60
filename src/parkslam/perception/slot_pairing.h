#ifndef PARKSLAM_PERCEPTION_SLOT_PAIRING_H_
#define PARKSLAM_PERCEPTION_SLOT_PAIRING_H_

// Slots from marking points alone (paper III-A, as DMPR-PS pairs its
// network's points): two marking points form an entrance line when they
// lie a slot's width apart and their separating lines leave the line to
// the same side, in the same direction; a candidate with a third marking
// point on it is removed (the paper's "more than two marking points"
// rule), and candidates of implausible length are discarded. The far
// corners are guessed from the standard depth of a perpendicular or a
// parallel slot.
//
// The classical detector (slot_detector.h) pairs its points with further
// checks on the painted lines it found; the learned detector, which finds
// no lines, uses these rules only.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "parkslam/common/lot_constants.h"
#include "parkslam/perception/slot_detector.h"

namespace parkslam::perception {

struct SlotPairingOptions {
  double pixels_per_m = 60.0;  // 600 px for 10 m (ps2.0)
  // Entrance lengths accepted as slots; longer than parallel_min_entrance_m
  // is a parallel slot.
  double min_entrance_m = 2.0;
  double max_entrance_m = 7.5;
  double parallel_min_entrance_m = 4.0;
  double standard_depth_m = kStandardSlotDepth_m;
  double parallel_depth_m = 2.5;
  // A parallel slot's separating lines stay in the image for this far
  // from both marking points (0: no check; DropParallelSlotsLeavingTheView).
  double parallel_min_depth_in_view_m = 0.8;
  // A slot with a corner within border_width_check_m of the image's border
  // is dropped when its width differs by more than border_width_share from
  // that of a slot sharing its other corner (0: no check;
  // DropOddSlotsAtTheBorder).
  double border_width_check_m = 0.5;
  double border_width_share = 0.15;
  // The separating lines of a slot's two points agree within this.
  double max_direction_difference_rad = 0.35;
  // A third marking point within this of the entrance line lies on it.
  double on_line_tolerance_m = 0.25;
  // The separating lines leave the entrance at least at this angle (angled
  // slots meet it at 45 degrees or more).
  double min_junction_angle_rad = 0.6;
  // Slots open towards the car, which stands at the image's centre, unless
  // the car stands less than max_vehicle_depth_in_row_m past the entrance of
  // a slot narrower than parallel_min_entrance_m, inside its row (parking
  // into it; 0: never). SlotDetectorOptions says why.
  bool require_entrance_facing_vehicle = true;
  double max_vehicle_depth_in_row_m = 4.0;
  // A marking point inside a slot (beyond on_line_tolerance_m past its
  // entrance), weaker than both of the slot's points, is dropped with the
  // slots it makes: painted digits inside a slot make such points.
  bool drop_points_inside_slots = true;

  bool IsValid(std::string* error) const;

  // The field list, walked by the options file reader (io/options_yaml.h).
  template <typename V>
  void VisitFields(V& v) {
    v("pixels_per_m", pixels_per_m);
    v("min_entrance_m", min_entrance_m);
    v("max_entrance_m", max_entrance_m);
    v("parallel_min_entrance_m", parallel_min_entrance_m);
    v("standard_depth_m", standard_depth_m);
    v("parallel_depth_m", parallel_depth_m);
    v("parallel_min_depth_in_view_m", parallel_min_depth_in_view_m);
    v("border_width_check_m", border_width_check_m);
    v("border_width_share", border_width_share);
    v("max_direction_difference_rad", max_direction_difference_rad);
    v("on_line_tolerance_m", on_line_tolerance_m);
    v("min_junction_angle_rad", min_junction_angle_rad);
    v("require_entrance_facing_vehicle", require_entrance_facing_vehicle);
    v("max_vehicle_depth_in_row_m", max_vehicle_depth_in_row_m);
    v("drop_points_inside_slots", drop_points_inside_slots);
  }
};

// Slots from `points` in an image of `image_size` (whose centre is the
// car). DetectedSlot::marking_points index into `points`; its confidence is
// the geometric mean of the two points' scores.
std::vector<DetectedSlot> PairMarkingPoints(const std::vector<MarkingPoint>& points,
                                            const cv::Size& image_size,
                                            const SlotPairingOptions& options);

// Drops the parallel slots (entrance at least parallel_min_entrance_m)
// whose separating lines leave the image within
// parallel_min_depth_in_view_m of either marking point. A row's end line
// at the image's border pairs as a parallel slot: its two ends meet the
// row's entrance and back lines, which leave the view a few decimetres on
// and pass for that slot's separating lines. The classical detector
// rejects it by its stem rule (slot_detector.cc), which needs the lines
// this detector does not find. Applied after the paint check, which may
// still find a missed point across such a candidate.
void DropParallelSlotsLeavingTheView(const cv::Size& image_size, const SlotPairingOptions& options,
                                     std::vector<DetectedSlot>* slots);

// Drops a slot with an entrance corner within border_width_check_m of the
// image's border whose width differs by more than border_width_share from
// a neighbour's in its row (a slot sharing its other marking point): a
// junction the border cuts shows too little of its arms, and the network
// puts it where the paint leaves the image, or fires on what the border
// cuts of an ID; slots of one row are as wide as each other.
void DropOddSlotsAtTheBorder(const cv::Size& image_size, const SlotPairingOptions& options,
                             std::vector<DetectedSlot>* slots);

}  // namespace parkslam::perception

#endif  // PARKSLAM_PERCEPTION_SLOT_PAIRING_H_
