#include "parkslam/mapping/map_graph.h"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "parkslam/mapping/association.h"
#include "parkslam/mapping/costs/angle.h"
#include "parkslam/mapping/costs/max_mixture_corner_factor.h"
#include "parkslam/mapping/costs/odometry_factor.h"
#include "parkslam/mapping/costs/prior_factor.h"
#include "parkslam/mapping/costs/slot_shape_factor.h"
#include "parkslam/mapping/costs/tag_observation_factor.h"
#include "parkslam/mapping/slot_management.h"

namespace parkslam::mapping {
namespace {

double Square(double x) { return x * x; }

// The records a bounded windowed solve takes (MapperOptions::
// window_history_observations), in order: the window's, which are the last
// ones since records come in keyframe order, and for each landmark they
// name (added to *free) its latest `history` older ones, from `index`
// (landmark -> its records, oldest first). The work does not grow with the
// drive.
template <typename Record, typename Landmarks>
std::vector<size_t> BoundedWindowRecords(const std::vector<Record>& records,
                                         const std::vector<std::vector<size_t>>& index,
                                         int first_free, int history, Landmarks landmarks_of,
                                         std::set<int>* free) {
  std::vector<size_t> in_play;
  for (size_t r = records.size(); r-- > 0 && records[r].keyframe >= first_free;) {
    for (int landmark : landmarks_of(records[r])) free->insert(landmark);
    in_play.push_back(r);
  }
  for (int landmark : *free) {
    const std::vector<size_t>& own = index[static_cast<size_t>(landmark)];
    int taken = 0;
    for (size_t i = own.size(); i-- > 0 && taken < history;) {
      if (records[own[i]].keyframe >= first_free) continue;
      in_play.push_back(own[i]);
      ++taken;
    }
  }
  std::sort(in_play.begin(), in_play.end());
  in_play.erase(std::unique(in_play.begin(), in_play.end()), in_play.end());
  return in_play;
}

// Slot records in play with history 0 (the final solve): the window's, and
// every record naming a slot the window sees (into *free).
std::vector<size_t> AllSlotRecordsOfFreeSlots(const std::vector<SlotRecord>& records,
                                              int first_free, std::set<int>* free) {
  for (const SlotRecord& record : records) {
    if (record.keyframe >= first_free)
      free->insert(record.candidates.begin(), record.candidates.end());
  }
  std::vector<size_t> in_play;
  for (size_t r = 0; r < records.size(); ++r) {
    const SlotRecord& record = records[r];
    const bool touches_free = std::any_of(record.candidates.begin(), record.candidates.end(),
                                          [&](int c) { return free->count(c) > 0; });
    if (record.keyframe >= first_free || touches_free) in_play.push_back(r);
  }
  return in_play;
}

// The same for tags.
std::vector<size_t> AllTagRecordsOfFreeTags(const std::vector<TagRecord>& records, int first_free,
                                            std::set<int>* free) {
  for (const TagRecord& record : records) {
    if (record.keyframe >= first_free) free->insert(record.tag);
  }
  std::vector<size_t> in_play;
  for (size_t r = 0; r < records.size(); ++r) {
    if (free->count(records[r].tag) > 0) in_play.push_back(r);
  }
  return in_play;
}

// The joint covariance of n corners (2n x 2n, corner a at rows 2a, 2a+1)
// moved to the gauge that holds their rigid motion as a whole: each
// corner's uncertainty relative to the others, the error left once the map
// is laid rigidly onto the lot (as `eval-map` lays it), not the uncertainty
// of the path from the first keyframe to it.
//
// With the centroid m of the corners p_a, d_a = p_a - m, the RMS radius L
// and J the rotation by +90 degrees, a small rigid motion (t, theta) moves
// p_a by A_a (t, L theta), A_a = [I_2, J d_a / L]. The best rigid fit of
// errors e removes A (A^T A)^-1 A^T e, so the errors left are M e with
// M = I - A (A^T A)^-1 A^T, and their covariance M P M^T. That is the
// covariance in the gauge C^T dx = 0 with C = A on the corners: covariances
// of two gauges are related by Q P Q^T, Q = I - G (C^T G)^-1 C^T for the
// rigid motions G of the whole graph (Triggs et al., "Bundle Adjustment --
// A Modern Synthesis", 2000, section 9), and on the corners Q is M.
Eigen::MatrixXd RelativeToTheCorners(const Eigen::MatrixXd& corners, const Eigen::MatrixXd& joint) {
  const Eigen::Index n = corners.rows();
  const Eigen::RowVector2d centroid = corners.colwise().mean();
  const Eigen::MatrixXd d = corners.rowwise() - centroid;
  const double radius_m = std::sqrt(d.squaredNorm() / static_cast<double>(n));
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 3);
  for (Eigen::Index a = 0; a < n; ++a) {
    A(2 * a, 0) = A(2 * a + 1, 1) = 1.0;
    A(2 * a, 2) = -d(a, 1) / radius_m;
    A(2 * a + 1, 2) = d(a, 0) / radius_m;
  }
  // M = I - A K with K = (A^T A)^-1 A^T (3 x 2n): M P M^T expanded, so that
  // no 2n x 2n product but P's own is formed.
  const Eigen::MatrixXd K = (A.transpose() * A).ldlt().solve(A.transpose());
  const Eigen::MatrixXd PKt = joint * K.transpose();  // 2n x 3
  const Eigen::Matrix3d KPKt = K * PKt;
  Eigen::MatrixXd relative = joint - A * PKt.transpose() - PKt * A.transpose();
  relative += A * KPKt * A.transpose();
  return relative;
}

// One graph being built over the state.
class GraphBuilder {
 public:
  GraphBuilder(MapState* state, int first_free, const MapperOptions& options)
      : state_(*state), first_free_(first_free), options_(options), problem_(ProblemOptions()) {}

  // Odometry between consecutive keyframes (the first links to the last
  // fixed one), all through the one wheel scale error: free, with its
  // prior, where the whole drive is in the graph (a window alone would pull
  // it back to the prior with a fraction of the evidence), held otherwise.
  void AddOdometry() {
    const int count = static_cast<int>(state_.keyframes.size());
    double* scale = state_.wheel_scale_error.data();
    for (int k = std::max(1, first_free_); k < count; ++k) {
      const Keyframe& keyframe = state_.keyframes[k];
      // Without the scale's estimate, the distances as the odometry gave them.
      const double odometry_wheel_scale =
          state_.wheel_scale_sigma > 0.0 ? keyframe.odometry_wheel_scale : 0.0;
      problem_.AddResidualBlock(OdometryFactor::Create(keyframe.T_previous_this,
                                                       keyframe.covariance, odometry_wheel_scale),
                                nullptr, Pose(k - 1), Pose(k), scale);
    }
    if (count == 1) Pose(0);
    if (!problem_.HasParameterBlock(scale)) return;
    if (first_free_ == 0 && state_.wheel_scale_sigma > 0.0) {
      problem_.AddResidualBlock(ScalarPriorFactor::Create(0.0, state_.wheel_scale_sigma), nullptr,
                                scale);
    } else {
      problem_.SetParameterBlockConstant(scale);
    }
  }

  // Slot observations: one block per observation over all its candidates.
  // Slots seen in the window are free; their older observations enter too
  // (older poses held fixed), so a revisited slot keeps its earlier
  // evidence. Then the rectangular constraint of every free slot (paper
  // III-A).
  void AddSlots(int history) {
    std::set<int> free_slots;
    const std::vector<size_t> in_play =
        history == 0 ? AllSlotRecordsOfFreeSlots(state_.slot_records, first_free_, &free_slots)
                     : BoundedWindowRecords(
                           state_.slot_records, state_.slot_record_index, first_free_, history,
                           [](const SlotRecord& record) { return record.candidates; }, &free_slots);
    std::set<int> fixed_slots;
    for (const size_t r : in_play) {
      AddSlotRecord(r);
      for (int s : state_.slot_records[r].candidates) {
        if (free_slots.count(s) == 0) fixed_slots.insert(s);
      }
    }
    for (int s : fixed_slots) {
      for (int j = 0; j < kSlotCorners; ++j) {
        problem_.SetParameterBlockConstant(state_.slots[s].corners[j].data());
      }
    }
    for (int s : free_slots) {
      SlotLandmark& slot = state_.slots[s];
      problem_.AddResidualBlock(
          SlotShapeFactor::Create(slot.angle_rad, slot.width_m, slot.depth_m,
                                  options_.shape_angle_sigma_rad, options_.shape_length_sigma_m),
          nullptr, slot.corners[0].data(), slot.corners[1].data(), slot.corners[2].data(),
          slot.corners[3].data());
    }
  }

  void AddTags(int history) {
    std::set<int> free_tags;
    const std::vector<size_t> in_play =
        history == 0
            ? AllTagRecordsOfFreeTags(state_.tag_records, first_free_, &free_tags)
            : BoundedWindowRecords(
                  state_.tag_records, state_.tag_record_index, first_free_, history,
                  [](const TagRecord& record) { return std::vector<int>{record.tag}; }, &free_tags);
    for (const size_t r : in_play) {
      const TagRecord& record = state_.tag_records[r];
      double* tag_block = state_.tags[record.tag].pose.data();
      if (!problem_.HasParameterBlock(tag_block)) {
        problem_.AddParameterBlock(tag_block, 3, &pose_manifold_);
      }
      problem_.AddResidualBlock(TagObservationFactor::Create(record.observation.p_vehicle,
                                                             record.observation.yaw_vehicle_rad,
                                                             record.observation.covariance_vehicle,
                                                             record.observation.yaw_sigma_rad),
                                nullptr, Pose(record.keyframe), tag_block);
    }
  }

  void Solve(int max_iterations, MapGraphSolve* result) {
    result->residual_blocks = problem_.NumResidualBlocks();
    ceres::Solver::Options solver_options;
    solver_options.max_num_iterations = max_iterations;
    solver_options.num_threads = 1;
    solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    solver_options.trust_region_strategy_type =
        options_.trust_region == TrustRegion::kDogleg ? ceres::DOGLEG : ceres::LEVENBERG_MARQUARDT;
    solver_options.initial_trust_region_radius = options_.initial_trust_region_radius;
    solver_options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem_, &summary);
    if (summary.termination_type == ceres::FAILURE) {
      throw std::runtime_error("Mapper: the solver refused to run or failed: " + summary.message);
    }
    result->iterations = static_cast<int>(summary.iterations.size());
    result->final_cost = summary.final_cost;
  }

  // The covariances of ComputeCornerCovariances (map_graph.h): of the
  // corners the map will show as seen, jointly, in this graph's gauge (the
  // first keyframe held), then moved to the gauge of the corners' own rigid
  // motion (RelativeToTheCorners). Ceres' SPARSE_QR at the present values,
  // the mixtures at the components they pick. False when Ceres fails (a
  // graph that leaves more than its gauge free), for fewer than two corners
  // and for more than kMaxJointCorners.
  bool ComputeCovariances(CornerCovariances* out) {
    struct Seen {
      size_t slot;
      int corner;
      const double* block;
    };
    std::vector<Seen> seen;
    for (size_t s = 0; s < state_.slots.size(); ++s) {
      const SlotLandmark& slot = state_.slots[s];
      if (!InTheMap(slot, options_)) continue;
      for (int j = 0; j < kSlotCorners; ++j) {
        const double* block = slot.corners[j].data();
        if (slot.corner_observations[j] == 0 || !problem_.HasParameterBlock(block) ||
            problem_.IsParameterBlockConstant(block)) {
          continue;
        }
        seen.push_back({s, j, block});
      }
    }
    // The joint covariance is dense: 2,000 corners (about 500 slots) take
    // 128 MB and Ceres' blocks as much again. A larger map keeps the
    // sighting-count sigmas (the caller's fallback).
    constexpr size_t kMaxJointCorners = 2000;
    if (seen.size() < 2 || seen.size() > kMaxJointCorners) return false;
    std::vector<std::pair<const double*, const double*>> wanted;
    for (size_t a = 0; a < seen.size(); ++a) {
      for (size_t b = a; b < seen.size(); ++b) wanted.emplace_back(seen[a].block, seen[b].block);
    }
    ceres::Covariance::Options covariance_options;
    covariance_options.algorithm_type = ceres::SPARSE_QR;
    covariance_options.num_threads = 1;
    ceres::Covariance covariance(covariance_options);
    if (!covariance.Compute(wanted, &problem_)) return false;
    const Eigen::Index n = static_cast<Eigen::Index>(seen.size());
    Eigen::MatrixXd joint(2 * n, 2 * n);
    Eigen::MatrixXd corners(n, 2);
    for (Eigen::Index a = 0; a < n; ++a) {
      corners.row(a) = state_.slots[seen[a].slot].Corner(seen[a].corner).transpose();
      for (Eigen::Index b = a; b < n; ++b) {
        Eigen::Matrix<double, 2, 2, Eigen::RowMajor> block;
        if (!covariance.GetCovarianceBlock(seen[a].block, seen[b].block, block.data())) {
          return false;
        }
        joint.block<2, 2>(2 * a, 2 * b) = block;
        joint.block<2, 2>(2 * b, 2 * a) = block.transpose();
      }
    }
    const Eigen::MatrixXd relative = RelativeToTheCorners(corners, joint);
    out->assign(state_.slots.size(), {});
    for (Eigen::Index a = 0; a < n; ++a) {
      (*out)[seen[a].slot][seen[a].corner] = relative.block<2, 2>(2 * a, 2 * a);
    }
    return true;
  }

  // Which component each mixture picked at the solution.
  void ReadBackChoices(MapGraphSolve* result) const {
    for (const MixtureBlock& m : mixtures_) {
      const int component = m.factor->ChosenComponent(m.blocks.data());
      const SlotRecord& record = state_.slot_records[m.record];
      const int chosen = component < 0 ? -1 : record.candidates[component];
      if (chosen != record.chosen) result->changed.push_back({m.record, record.chosen, chosen});
    }
  }

 private:
  struct MixtureBlock {
    size_t record;
    const MaxMixtureCornerFactor* factor;
    std::vector<double*> blocks;
  };

  static ceres::Problem::Options ProblemOptions() {
    ceres::Problem::Options o;
    o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return o;
  }

  // A keyframe's pose block, added on first use: held fixed before the
  // window, and the first keyframe always.
  double* Pose(int k) {
    double* block = state_.keyframes[k].pose.data();
    if (!problem_.HasParameterBlock(block)) {
      problem_.AddParameterBlock(block, 3, &pose_manifold_);
      if (k < first_free_ || k == 0) problem_.SetParameterBlockConstant(block);
    }
    return block;
  }

  void AddSlotRecord(size_t r) {
    const SlotRecord& record = state_.slot_records[r];
    std::vector<CornerMeasurement> measurements;
    for (int j = 0; j < kSlotCorners; ++j) {
      measurements.push_back(
          {record.observation.corners_vehicle[j],
           Eigen::Matrix2d::Identity() * Square(CornerSigma(record.observation, j, options_))});
    }
    std::vector<double*> blocks{Pose(record.keyframe)};
    for (int s : record.candidates) {
      for (int j = 0; j < kSlotCorners; ++j) blocks.push_back(state_.slots[s].corners[j].data());
    }
    auto* factor = new MaxMixtureCornerFactor(measurements, record.weights,
                                              record.has_null ? options_.null_weight : 0.0,
                                              options_.null_chi2);
    problem_.AddResidualBlock(factor, nullptr, blocks);
    if (record.has_null || record.candidates.size() > 1) mixtures_.push_back({r, factor, blocks});
  }

  MapState& state_;
  const int first_free_;
  const MapperOptions& options_;
  Pose2Manifold pose_manifold_;
  ceres::Problem problem_;  // after the manifold it refers to, destroyed first
  std::vector<MixtureBlock> mixtures_;
};

}  // namespace

MapGraphSolve SolveMapGraph(MapState* state, int first_free, int max_iterations, bool final,
                            const MapperOptions& options) {
  MapGraphSolve result;
  if (state->keyframes.empty()) return result;
  const int history = final ? 0 : options.window_history_observations;
  GraphBuilder graph(state, first_free, options);
  graph.AddOdometry();
  graph.AddSlots(history);
  graph.AddTags(history);
  graph.Solve(max_iterations, &result);
  graph.ReadBackChoices(&result);
  return result;
}

bool ComputeCornerCovariances(MapState* state, const MapperOptions& options,
                              CornerCovariances* covariances) {
  if (state->keyframes.empty()) return false;
  GraphBuilder graph(state, 0, options);
  graph.AddOdometry();
  graph.AddSlots(0);
  graph.AddTags(0);
  return graph.ComputeCovariances(covariances);
}

}  // namespace parkslam::mapping
