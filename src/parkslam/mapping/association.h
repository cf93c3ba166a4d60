#ifndef PARKSLAM_MAPPING_ASSOCIATION_H_
#define PARKSLAM_MAPPING_ASSOCIATION_H_

// Slot association (paper III-C): which slots of the map a slot observation
// may be. By ID (the slots whose votes agree with the reading, within
// id_search_radius_m) and by nearest neighbour (within nn_search_radius_m),
// each candidate weighted by geometry_weight plus its ID support; with
// Max-Mixture they all enter the factor graph beside a null hypothesis,
// without it the paper's baseline picks one. Reads the map state only.

#include "parkslam/mapping/map_state.h"
#include "parkslam/mapping/mapper_options.h"
#include "parkslam/sensor/sensor_data.h"

namespace parkslam::mapping {

// The corner angle of a slot observation at corner 0, counter-clockwise
// from the entrance to the side; plausible slots lie in (0, pi).
double SlotAngle(const SlotObservation& observation);

// A slot shape the detector can have seen: finite corners, a corner angle
// between 20 and 160 degrees, entrance and side longer than 0.5 m.
bool PlausibleSlot(const SlotObservation& observation);

// Per-corner standard deviation of an observation: the detector's for seen
// corners (with a floor), a loose one for guessed corners.
double CornerSigma(const SlotObservation& observation, int corner, const MapperOptions& options);

// How much the slot's ID votes support the reading, in [0, 1]: the
// probability mass of the reading's full-ID hypotheses on the slot's IDs,
// and for a partial reading the slot's IDs that match its read digit, at
// that digit's confidence.
double IdSupport(const SlotLandmark& slot, const SlotObservation& observation,
                 const MapperOptions& options);

struct SlotAssociation {
  // Neither a confident ID nor a neighbour: the observation makes a new
  // slot, under a temporary ID.
  bool new_slot = false;
  // Otherwise the record to add: its candidates (best first), their
  // weights, the null hypothesis (Max-Mixture only) and the chosen slot.
  SlotRecord record;
};

// Associates an observation made at `keyframe` (its pose from the state),
// the prediction's uncertainty grown with the distance driven since the
// last solve (prediction_sigma_m: MapperOptions::prediction_sigma_m +
// prediction_sigma_per_m * distance).
SlotAssociation AssociateSlot(const MapState& state, int keyframe,
                              const SlotObservation& observation, double prediction_sigma_m,
                              const MapperOptions& options);

}  // namespace parkslam::mapping

#endif  // PARKSLAM_MAPPING_ASSOCIATION_H_
