#include "parkslam/mapping/map_update.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "parkslam/common/alignment.h"
#include "parkslam/common/angles.h"
#include "parkslam/common/field_checker.h"

namespace parkslam::mapping {
namespace {

// Two points of one frame matched to two of another: a slot's entrance
// corners, or a tag's centre and a point 1 m out along its normal.
struct PointPair {
  Eigen::Vector2d p_old, p_new;
};
struct LandmarkPair {
  std::vector<PointPair> points;
};

std::vector<PointPair> TagPoints(const MapTag& old_tag, const MapTag& new_tag) {
  const auto out = [](const MapTag& t) -> Eigen::Vector2d {
    return t.p_map + Eigen::Vector2d(std::cos(t.yaw_map_rad), std::sin(t.yaw_map_rad));
  };
  return {{old_tag.p_map, new_tag.p_map}, {out(old_tag), out(new_tag)}};
}

// The rigid transform taking the new points onto the old in least squares
// (common/alignment.h).
SE2 FitRigid(const std::vector<PointPair>& pairs) {
  std::vector<Eigen::Vector2d> p_new, p_old;
  for (const PointPair& p : pairs) p_new.push_back(p.p_new), p_old.push_back(p.p_old);
  return AlignPointSets(p_new, p_old);
}

int Agreeing(const SE2& T_old_new, const std::vector<LandmarkPair>& pairs, double inlier_m,
             std::vector<PointPair>* points) {
  int agreeing = 0;
  for (const LandmarkPair& pair : pairs) {
    bool all = true;
    for (const PointPair& p : pair.points) {
      all = all && (T_old_new * p.p_new - p.p_old).norm() <= inlier_m;
    }
    if (!all) continue;
    ++agreeing;
    if (points != nullptr) points->insert(points->end(), pair.points.begin(), pair.points.end());
  }
  return agreeing;
}

bool Painted(const MapSlot& slot) { return !slot.id.empty() && !slot.temporary; }

Eigen::Vector2d EntranceMid(const MapSlot& slot) {
  return 0.5 * (slot.corners_map[0] + slot.corners_map[1]);
}

double EntranceYaw(const MapSlot& slot) {
  const Eigen::Vector2d d = slot.corners_map[1] - slot.corners_map[0];
  return std::atan2(d.y(), d.x());
}

// What the new drive's sighting says of an old slot, by its entrance
// corners (those it saw; the back ones are mostly guesses): both within
// same_place_m, the slot is where it was; both moved alike (by more than
// same_place_m, and within same_place_m of each other), it moved; else the
// sighting disagrees with itself (one corner put on a neighbour's line, as
// a detector does next to a slot painted anew) and says nothing.
enum class Sighting { kInPlace, kMoved, kDisputed };

Sighting Judge(const MapSlot& old_slot, const MapSlot& new_slot, double same_place_m) {
  std::vector<Eigen::Vector2d> moves;
  for (int k = 0; k < 2; ++k) {
    if (new_slot.corner_observed[k]) {
      moves.push_back(new_slot.corners_map[k] - old_slot.corners_map[k]);
    }
  }
  if (moves.empty()) {
    // Nothing seen of the entrance: the slot's middle alone.
    const double d = (EntranceMid(new_slot) - EntranceMid(old_slot)).norm();
    return d <= same_place_m ? Sighting::kInPlace : Sighting::kDisputed;
  }
  bool all_in_place = true, all_moved = true;
  for (const Eigen::Vector2d& m : moves) {
    all_in_place = all_in_place && m.norm() <= same_place_m;
    all_moved = all_moved && m.norm() > same_place_m;
  }
  if (all_in_place) return Sighting::kInPlace;
  if (all_moved && moves.size() == 2 && (moves[0] - moves[1]).norm() <= same_place_m) {
    return Sighting::kMoved;
  }
  return Sighting::kDisputed;
}

// Confirmed in place: the old geometry stays, but for corners the old map
// had only guessed and the new drive saw.
void Confirm(const MapSlot& seen, const std::string& label, MapSlot* slot) {
  for (int k = 0; k < kSlotCorners; ++k) {
    if (slot->corner_observed[k] || !seen.corner_observed[k]) continue;
    slot->corners_map[k] = seen.corners_map[k];
    slot->corner_observed[k] = true;
    slot->corner_sigma_m[k] = seen.corner_sigma_m[k];
  }
  slot->observation_count += seen.observation_count;
  slot->last_confirmed = label;
}

// Moved: the new geometry replaces the old.
void Replace(const MapSlot& seen, const std::string& label, MapSlot* slot) {
  slot->kind = seen.kind;
  slot->corners_map = seen.corners_map;
  slot->corner_observed = seen.corner_observed;
  slot->corner_sigma_m = seen.corner_sigma_m;
  slot->observation_count = seen.observation_count;
  slot->last_confirmed = label;
}

double SegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                       const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-12), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

bool SegmentsCross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                   const Eigen::Vector2d& d) {
  const auto side = [](const Eigen::Vector2d& o, const Eigen::Vector2d& p,
                       const Eigen::Vector2d& q) {
    const Eigen::Vector2d u = p - o, v = q - o;
    return u.x() * v.y() - u.y() * v.x();
  };
  return side(a, b, c) * side(a, b, d) < 0.0 && side(c, d, a) * side(c, d, b) < 0.0;
}

// The obstacle edges, each as a segment (a pillar's polygon closed).
std::vector<std::pair<int, std::pair<Eigen::Vector2d, Eigen::Vector2d>>> ObstacleEdges(
    const SemanticMap& map) {
  std::vector<std::pair<int, std::pair<Eigen::Vector2d, Eigen::Vector2d>>> edges;
  for (std::size_t i = 0; i < map.obstacles.size(); ++i) {
    const std::vector<Eigen::Vector2d>& p = map.obstacles[i].points_map;
    const bool closed = map.obstacles[i].kind == ObstacleKind::kPillar;
    for (std::size_t k = 0; k + 1 < p.size() + (closed ? 1 : 0); ++k) {
      edges.push_back({static_cast<int>(i), {p[k], p[(k + 1) % p.size()]}});
    }
  }
  return edges;
}

// Keyframes of the drive at which the front camera had the tag in view.
int KeyframesViewing(const MapTag& tag, const Trajectory& drive_old, const SemanticMap& old_map,
                     const MapUpdateOptions& o) {
  const auto edges = ObstacleEdges(old_map);
  const Eigen::Vector2d normal(std::cos(tag.yaw_map_rad), std::sin(tag.yaw_map_rad));
  int count = 0;
  for (const TimedPose& pose : drive_old) {
    const Eigen::Vector2d car =
        pose.T_map_vehicle * Eigen::Vector2d(o.camera_forward_m, 0.0);  // the camera
    const Eigen::Vector2d to_tag = tag.p_map - car;
    const double range_m = to_tag.norm();
    if (range_m > o.tag_view_range_m || range_m < 0.5) continue;
    const double bearing = AngleDiff(std::atan2(to_tag.y(), to_tag.x()), pose.T_map_vehicle.yaw());
    if (std::abs(bearing) > o.tag_view_half_angle_rad) continue;
    if (normal.dot(-to_tag) < 0.5 * range_m) continue;  // facing the car within 60 degrees
    // Sight from the car to a point just in front of the tag.
    const Eigen::Vector2d target = tag.p_map + 0.05 * normal;
    bool blocked = false;
    for (const auto& [index, edge] : edges) {
      if (index == tag.obstacle_index) continue;
      if (SegmentsCross(car, target, edge.first, edge.second)) blocked = true;
    }
    if (!blocked) ++count;
  }
  return count;
}

// The obstacle (of `map`) within 0.5 m of p, or -1.
int ObstacleNear(const SemanticMap& map, const Eigen::Vector2d& p) {
  int best = -1;
  double best_m = 0.5;
  for (const auto& [index, edge] : ObstacleEdges(map)) {
    const double d = SegmentDistance(p, edge.first, edge.second);
    if (d < best_m) best = index, best_m = d;
  }
  return best;
}

int TemporaryNumber(const std::string& id) {
  if (id.size() < 2 || id[0] != 't') return -1;
  if (id.find_first_not_of("0123456789", 1) != std::string::npos || id.size() > 9) return -1;
  return std::stoi(id.substr(1));
}

}  // namespace

bool MapUpdateOptions::IsValid(std::string* error) const {
  FieldChecker c(error);
  c.Require(alignment_inlier_m > 0.0 && alignment_inlier_m <= 5.0, "alignment_inlier_m",
            "must be in (0, 5] m");
  c.Require(alignment_min_pairs >= 1, "alignment_min_pairs", "must be at least 1");
  c.Require(alignment_min_share >= 0.0 && alignment_min_share <= 1.0, "alignment_min_share",
            "must be in [0, 1]");
  c.Require(same_place_m > 0.0 && same_place_m < same_slot_m, "same_place_m",
            "must be in (0, same_slot_m)");
  c.Require(same_slot_m <= 5.0, "same_slot_m", "must be at most 5 m");
  c.Require(same_slot_angle_rad > 0.0 && same_slot_angle_rad <= M_PI / 2, "same_slot_angle_rad",
            "must be in (0, pi/2]");
  c.Require(tag_view_range_m > 0.0 && tag_view_range_m <= 50.0, "tag_view_range_m",
            "must be in (0, 50] m");
  c.Require(tag_view_half_angle_rad > 0.0 && tag_view_half_angle_rad <= M_PI / 2,
            "tag_view_half_angle_rad", "must be in (0, pi/2]");
  c.Require(tag_view_min_keyframes >= 1, "tag_view_min_keyframes", "must be at least 1");
  c.Require(std::abs(camera_forward_m) <= 10.0, "camera_forward_m", "must be in [-10, 10] m");
  return c.ok();
}

SemanticMap UpdateMap(const SemanticMap& old_map, const SemanticMap& new_map,
                      const Trajectory& new_drive, const MapUpdateOptions& o,
                      MapUpdateReport* report) {
  std::string error;
  if (!o.IsValid(&error)) throw std::invalid_argument("map update: " + error);
  MapUpdateReport r;

  // 1. Alignment, from the landmarks both maps name alike.
  std::map<std::string, int> old_slot_by_id;
  for (std::size_t i = 0; i < old_map.slots.size(); ++i) {
    if (Painted(old_map.slots[i])) old_slot_by_id[old_map.slots[i].id] = static_cast<int>(i);
  }
  std::map<int, int> old_tag_by_id;
  for (std::size_t i = 0; i < old_map.tags.size(); ++i) {
    old_tag_by_id[old_map.tags[i].tag_id] = static_cast<int>(i);
  }
  std::vector<LandmarkPair> pairs;
  for (const MapSlot& s : new_map.slots) {
    const auto it = Painted(s) ? old_slot_by_id.find(s.id) : old_slot_by_id.end();
    if (it == old_slot_by_id.end() || !s.corner_observed[0] || !s.corner_observed[1]) continue;
    const MapSlot& old_slot = old_map.slots[it->second];
    pairs.push_back({{{old_slot.corners_map[0], s.corners_map[0]},
                      {old_slot.corners_map[1], s.corners_map[1]}}});
  }
  for (const MapTag& t : new_map.tags) {
    const auto it = old_tag_by_id.find(t.tag_id);
    if (it != old_tag_by_id.end()) pairs.push_back({TagPoints(old_map.tags[it->second], t)});
  }
  r.alignment_pairs = static_cast<int>(pairs.size());
  SE2 T_old_new;
  int best = 0;
  for (const LandmarkPair& pair : pairs) {
    const SE2 proposal = FitRigid(pair.points);
    const int agreeing = Agreeing(proposal, pairs, o.alignment_inlier_m, nullptr);
    if (agreeing > best) best = agreeing, T_old_new = proposal;
  }
  for (int round = 0; round < 2 && best > 0; ++round) {
    std::vector<PointPair> points;
    Agreeing(T_old_new, pairs, o.alignment_inlier_m, &points);
    T_old_new = FitRigid(points);
  }
  r.alignment_inliers = Agreeing(T_old_new, pairs, o.alignment_inlier_m, nullptr);
  r.T_old_new = T_old_new;
  if (r.alignment_inliers < o.alignment_min_pairs ||
      r.alignment_inliers < o.alignment_min_share * r.alignment_pairs) {
    throw std::runtime_error(
        "map update: " + std::to_string(r.alignment_inliers) + " of " +
        std::to_string(r.alignment_pairs) +
        " landmarks named alike in both maps agree on where the new drive "
        "lies in the old map (at least " +
        std::to_string(o.alignment_min_pairs) + ", and " +
        std::to_string(static_cast<int>(std::lround(100.0 * o.alignment_min_share))) +
        " % of them, needed): is it a drive of this lot?");
  }

  // The new map and its drive in the old map's frame.
  SemanticMap seen = new_map;
  for (MapSlot& s : seen.slots) {
    for (Eigen::Vector2d& c : s.corners_map) c = T_old_new * c;
  }
  for (MapTag& t : seen.tags) {
    t.p_map = T_old_new * t.p_map;
    t.yaw_map_rad = NormalizeAngle(t.yaw_map_rad + T_old_new.yaw());
  }
  const Trajectory drive_old = Transformed(T_old_new, new_drive);

  // 2. Slots. Matches by painted ID first, then by place among the rest.
  SemanticMap out = old_map;
  // The old map's entrance stands (its frame is kept); a map without one
  // takes the new drive's.
  if (!out.entrance && new_map.entrance) out.entrance = T_old_new * *new_map.entrance;
  std::vector<bool> old_taken(out.slots.size(), false);
  std::vector<int> match(seen.slots.size(), -1);
  // The old slot (not yet taken, unless any_slot) that the new slot
  // covers, or -1.
  const auto covered = [&](const MapSlot& s, bool any_slot = false) {
    int found = -1;
    double best_m = o.same_slot_m;
    for (std::size_t i = 0; i < old_map.slots.size(); ++i) {
      if (old_taken[i] && !any_slot) continue;
      const double d = (EntranceMid(out.slots[i]) - EntranceMid(s)).norm();
      if (d >= best_m ||
          std::abs(AngleDiff(EntranceYaw(out.slots[i]), EntranceYaw(s))) > o.same_slot_angle_rad) {
        continue;
      }
      best_m = d;
      found = static_cast<int>(i);
    }
    return found;
  };
  for (std::size_t n = 0; n < seen.slots.size(); ++n) {
    const MapSlot& s = seen.slots[n];
    if (!Painted(s)) continue;
    const auto it = old_slot_by_id.find(s.id);
    if (it == old_slot_by_id.end() || old_taken[it->second]) continue;
    // An ID far from its old place, where another old slot lies, is more
    // likely misread than moved: that slot's, by place, below.
    const MapSlot& old_slot = out.slots[it->second];
    if ((EntranceMid(old_slot) - EntranceMid(s)).norm() > o.same_slot_m) {
      const int other = covered(s);
      if (other >= 0 && other != it->second) continue;
    }
    match[n] = it->second;
    old_taken[it->second] = true;
  }
  for (std::size_t n = 0; n < seen.slots.size(); ++n) {
    if (match[n] >= 0) continue;
    match[n] = covered(seen.slots[n]);
    if (match[n] >= 0) old_taken[match[n]] = true;
  }
  std::vector<bool> old_seen(out.slots.size(), false);
  int next_temporary = 0;
  for (const MapSlot& s : out.slots)
    next_temporary = std::max(next_temporary, TemporaryNumber(s.id));
  std::map<std::string, int> id_used;
  for (std::size_t i = 0; i < out.slots.size(); ++i) {
    if (!out.slots[i].id.empty()) id_used[out.slots[i].id] = static_cast<int>(i);
  }
  for (std::size_t n = 0; n < seen.slots.size(); ++n) {
    const MapSlot& s = seen.slots[n];
    if (match[n] < 0) {
      // Over an old slot another sighting has taken already: the new map
      // saw one slot twice (a detection straddling two).
      if (covered(s, true) >= 0) {
        ++r.slots_disputed;
        continue;
      }
      MapSlot added = s;
      if (added.id.empty() || added.temporary || id_used.contains(added.id)) {
        added.id = "t" + std::to_string(++next_temporary);
        added.temporary = true;
      }
      added.last_confirmed = o.label;
      id_used[added.id] = static_cast<int>(out.slots.size());
      out.slots.push_back(added);
      ++r.slots_added;
      continue;
    }
    MapSlot& slot = out.slots[match[n]];
    old_seen[match[n]] = true;
    // A new painted ID where the old slot had another, or only a temporary
    // one: repainted (unless another slot of the map has it).
    if (Painted(s) && s.id != slot.id && !id_used.contains(s.id)) {
      id_used.erase(slot.id);
      slot.id = s.id;
      slot.temporary = false;
      slot.id_legible = true;
      id_used[slot.id] = match[n];
      ++r.slots_repainted;
    }
    switch (Judge(slot, s, o.same_place_m)) {
      case Sighting::kInPlace:
        Confirm(s, o.label, &slot);
        ++r.slots_confirmed;
        break;
      case Sighting::kMoved:
        Replace(s, o.label, &slot);
        ++r.slots_moved;
        break;
      case Sighting::kDisputed:
        ++r.slots_disputed;  // kept as it was
        break;
    }
  }
  for (std::size_t i = 0; i < old_map.slots.size(); ++i) r.slots_unconfirmed += old_seen[i] ? 0 : 1;

  // 3. Tags.
  std::vector<bool> tag_seen(out.tags.size(), false);
  for (const MapTag& t : seen.tags) {
    const auto it = old_tag_by_id.find(t.tag_id);
    if (it == old_tag_by_id.end()) {
      MapTag added = t;
      added.obstacle_index = ObstacleNear(out, t.p_map);
      added.last_confirmed = o.label;
      out.tags.push_back(added);
      ++r.tags_added;
      continue;
    }
    MapTag& tag = out.tags[it->second];
    tag_seen[it->second] = true;
    if ((tag.p_map - t.p_map).norm() > o.same_place_m) {
      tag.p_map = t.p_map;
      tag.yaw_map_rad = t.yaw_map_rad;
      tag.obstacle_index = ObstacleNear(out, t.p_map);
      ++r.tags_moved;
    } else {
      ++r.tags_confirmed;
    }
    tag.last_confirmed = o.label;
  }
  // Old tags the drive had in view and did not find are gone; a drive that
  // found no tag at all (no front camera) removes none.
  std::vector<MapTag> kept;
  for (std::size_t i = 0; i < out.tags.size(); ++i) {
    if (i < tag_seen.size() && !tag_seen[i]) {
      if (!seen.tags.empty() &&
          KeyframesViewing(out.tags[i], drive_old, old_map, o) >= o.tag_view_min_keyframes) {
        ++r.tags_removed;
        continue;
      }
      ++r.tags_unconfirmed;
    }
    kept.push_back(out.tags[i]);
  }
  out.tags = std::move(kept);
  out.metadata["updated_by"] = o.label;
  if (report != nullptr) *report = r;
  return out;
}

}  // namespace parkslam::mapping
