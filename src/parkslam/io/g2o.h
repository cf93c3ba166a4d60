#ifndef PARKSLAM_IO_G2O_H_
#define PARKSLAM_IO_G2O_H_

// Planar pose graphs in the g2o text format, the field's common exchange
// format for SLAM benchmark graphs (Intel, M3500, ...). One element a line:
//
//   VERTEX_SE2 id x y theta
//   VERTEX_XY id x y
//   EDGE_SE2 from to dx dy dtheta I11 I12 I13 I22 I23 I33
//   EDGE_SE2_XY pose point dx dy I11 I12 I22
//   FIX id [id ...]
//   EDGE_SE2_MIXTURE a b 2 EDGE_SE2 w a b dx dy dtheta I.. EDGE_SE2 w a b dx dy dtheta I..
//
// I.. is the upper triangle of the information matrix, row by row. A
// mixture line (Agarwal and Olson's Max-Mixture plugin for g2o) is read where
// it is a closure and its null hypothesis: one measurement, one component's
// information a scale s < 1 of the other's; the closure becomes an edge and
// the null (weight ratio, s) the graph's file_null, one per file. The writer
// writes plain EDGE_SE2 edges. Lines
// starting with '#' and blank lines are skipped; any other element type is
// an error naming its line (3D types and TORO's VERTEX2/EDGE2 are not read).

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include "parkslam/graph/pose_graph.h"

namespace parkslam::io {

// Throws IoError naming the source, the line and the field
// ("m3500.g2o:12: EDGE_SE2.I22: not a finite number"): wrong field counts,
// numbers that are not finite or beyond the plausible ranges
// (docs/plausible_ranges.md), duplicate vertex ids, edges naming vertices
// that do not exist, information matrices that are not positive definite,
// and a graph without a pose.
// The most poses a graph may have: a 20,000-pose grid solves in 12 s and
// 245 MB on two cores; one of 50,000 took over 5 minutes, 100,000 over 13
// minutes and 5 GB.
inline constexpr std::size_t kMaxG2oPoses = 20'000;
// The most edges (pose and point edges together): ten a pose at the pose
// limit. Two million took over 2.4 GB before a Max-Mixture solve of them
// had done; the standard sets have at most 6,453 (M3500 with its 1,000
// outliers).
inline constexpr std::size_t kMaxG2oEdges = 200'000;
graph::PoseGraph ParseG2o(std::string_view text, const std::string& source_name);
graph::PoseGraph ReadG2o(const std::filesystem::path& path);

// Vertices (in id order), FIX, then the edges, with every number written
// so that it reads back exactly.
std::string FormatG2o(const graph::PoseGraph& graph);
// Writes atomically.
void WriteG2o(const std::filesystem::path& path, const graph::PoseGraph& graph);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_G2O_H_
