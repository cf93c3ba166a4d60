#include "parkslam/io/g2o.h"

#include <Eigen/Cholesky>
#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "parkslam/common/plausible_ranges.h"
#include "parkslam/io/atomic_file.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/text_util.h"

namespace parkslam::io {
namespace {

constexpr std::size_t kMaxFields = 16;

struct Line {
  const std::string* source;
  int number;
  std::string_view type;
  std::array<std::string_view, kMaxFields> fields;
  std::size_t count;  // fields after the type

  [[noreturn]] void Fail(std::string_view field, std::string_view what) const {
    ThrowIoError(*source, number,
                 std::string(type) + (field.empty() ? "" : ".") + std::string(field), what);
  }
  void ExpectCount(std::size_t expected) const {
    if (count != expected) {
      Fail("", "expected " + std::to_string(expected) + " values after the type, found " +
                   std::to_string(count));
    }
  }
  int Id(std::size_t i, std::string_view name) const {
    const std::optional<std::int64_t> id = text::ParseInt64(fields[i]);
    if (!id || *id < 0 || *id > std::numeric_limits<int>::max()) {
      Fail(name, "not a vertex id (an integer in [0, 2^31)) " + text::Quoted(fields[i]));
    }
    return static_cast<int>(*id);
  }
  double Number(std::size_t i, std::string_view name, double max_abs, std::string_view unit) const {
    const double value = text::ParseFiniteDouble(fields[i], *source, number,
                                                 std::string(type) + "." + std::string(name));
    if (std::abs(value) > max_abs) Fail(name, text::BeyondPlausible(value, max_abs, unit));
    return value;
  }
};

// Splits at spaces and tabs: the type, then up to kMaxFields values.
Line Tokenize(std::string_view text, const std::string& source, int number) {
  Line line{&source, number, {}, {}, 0};
  std::size_t i = 0;
  bool have_type = false;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    if (i == text.size()) break;
    const std::size_t start = i;
    while (i < text.size() && text[i] != ' ' && text[i] != '\t') ++i;
    const std::string_view token = text.substr(start, i - start);
    if (!have_type) {
      line.type = token;
      have_type = true;
    } else {
      if (line.count < kMaxFields) line.fields[line.count] = token;
      ++line.count;
    }
  }
  return line;
}

// Information entries of an upper triangle: any finite value up to this
// (sigmas down to a micrometre or a microradian).
constexpr double kMaxInformation = 1e12;

template <int N>
Eigen::Matrix<double, N, N> Information(const Line& line, std::size_t first) {
  Eigen::Matrix<double, N, N> information;
  std::size_t k = first;
  for (int r = 0; r < N; ++r) {
    for (int c = r; c < N; ++c, ++k) {
      const char name[4] = {'I', static_cast<char>('1' + r), static_cast<char>('1' + c), '\0'};
      information(r, c) = information(c, r) = line.Number(k, name, kMaxInformation, "");
    }
  }
  if (Eigen::LLT<Eigen::Matrix<double, N, N>>(information).info() != Eigen::Success) {
    line.Fail("I", "the information matrix is not positive definite");
  }
  return information;
}

void AppendNumbers(std::string* out, std::initializer_list<double> values) {
  for (double v : values) {
    out->push_back(' ');
    text::AppendDouble(out, v);
  }
}

// What the lines of a file gave so far, with the line of each element
// for the messages.
struct G2oParse {
  graph::PoseGraph graph;
  std::map<int, int> vertex_line;  // id -> line that defined it
  std::vector<int> pose_edge_lines, point_edge_lines, fix_lines;
  std::vector<int> fix_ids;
};

// One element line into the graph.
void ParseElement(const Line& line, G2oParse* p) {
  auto define = [&](int id) {
    if (const auto it = p->vertex_line.find(id); it != p->vertex_line.end()) {
      line.Fail("id", "vertex " + std::to_string(id) + " is already defined on line " +
                          std::to_string(it->second));
    }
    p->vertex_line[id] = line.number;
  };
  if (line.type == "VERTEX_SE2") {
    line.ExpectCount(4);
    const int id = line.Id(0, "id");
    define(id);
    p->graph.poses[id] =
        SE2(line.Number(1, "x", kMaxCoordinate_m, "m"), line.Number(2, "y", kMaxCoordinate_m, "m"),
            line.Number(3, "theta", kMaxAngle_rad, "rad"));
  } else if (line.type == "VERTEX_XY") {
    line.ExpectCount(3);
    const int id = line.Id(0, "id");
    define(id);
    p->graph.points[id] = Eigen::Vector2d(line.Number(1, "x", kMaxCoordinate_m, "m"),
                                          line.Number(2, "y", kMaxCoordinate_m, "m"));
  } else if (line.type == "EDGE_SE2") {
    line.ExpectCount(11);
    graph::PoseEdge edge;
    edge.from = line.Id(0, "from");
    edge.to = line.Id(1, "to");
    if (edge.from == edge.to) line.Fail("to", "an edge from a vertex to itself");
    edge.T_from_to = SE2(line.Number(2, "dx", kMaxCoordinate_m, "m"),
                         line.Number(3, "dy", kMaxCoordinate_m, "m"),
                         line.Number(4, "dtheta", kMaxAngle_rad, "rad"));
    edge.information = Information<3>(line, 5);
    p->graph.pose_edges.push_back(edge);
    p->pose_edge_lines.push_back(line.number);
  } else if (line.type == "EDGE_SE2_XY") {
    line.ExpectCount(7);
    graph::PointEdge edge;
    edge.pose = line.Id(0, "pose");
    edge.point = line.Id(1, "point");
    edge.p_pose = Eigen::Vector2d(line.Number(2, "dx", kMaxCoordinate_m, "m"),
                                  line.Number(3, "dy", kMaxCoordinate_m, "m"));
    edge.information = Information<2>(line, 4);
    p->graph.point_edges.push_back(edge);
    p->point_edge_lines.push_back(line.number);
  } else if (line.type == "FIX") {
    if (line.count == 0) line.Fail("", "expected at least one vertex id");
    if (line.count > kMaxFields) line.Fail("", "more than 16 ids on one line");
    for (std::size_t i = 0; i < line.count; ++i) {
      p->fix_ids.push_back(line.Id(i, "id"));
      p->fix_lines.push_back(line.number);
    }
  } else {
    line.Fail("",
              "unknown element type (this reader takes VERTEX_SE2, VERTEX_XY, EDGE_SE2, "
              "EDGE_SE2_XY and FIX)");
  }
}

// References, once every vertex is known (files may list edges first); the
// FIX lines into the fixed set.
void ResolveReferences(const std::string& source_name, G2oParse* p) {
  for (size_t i = 0; i < p->graph.pose_edges.size(); ++i) {
    const graph::PoseEdge& e = p->graph.pose_edges[i];
    for (const auto& [id, field] : {std::pair{e.from, "from"}, std::pair{e.to, "to"}}) {
      if (!p->graph.poses.contains(id)) {
        ThrowIoError(source_name, p->pose_edge_lines[i], std::string("EDGE_SE2.") + field,
                     "no VERTEX_SE2 " + std::to_string(id));
      }
    }
  }
  for (size_t i = 0; i < p->graph.point_edges.size(); ++i) {
    const graph::PointEdge& e = p->graph.point_edges[i];
    if (!p->graph.poses.contains(e.pose)) {
      ThrowIoError(source_name, p->point_edge_lines[i], "EDGE_SE2_XY.pose",
                   "no VERTEX_SE2 " + std::to_string(e.pose));
    }
    if (!p->graph.points.contains(e.point)) {
      ThrowIoError(source_name, p->point_edge_lines[i], "EDGE_SE2_XY.point",
                   "no VERTEX_XY " + std::to_string(e.point));
    }
  }
  for (size_t i = 0; i < p->fix_ids.size(); ++i) {
    if (!p->vertex_line.contains(p->fix_ids[i])) {
      ThrowIoError(source_name, p->fix_lines[i], "FIX.id",
                   "no vertex " + std::to_string(p->fix_ids[i]));
    }
    p->graph.fixed.insert(p->fix_ids[i]);
  }
}

}  // namespace

graph::PoseGraph ParseG2o(std::string_view content, const std::string& source_name) {
  G2oParse p;
  text::LineCursor lines(content);
  std::string_view raw;
  while (lines.Next(&raw)) {
    const std::string_view trimmed = text::Trim(raw);
    if (trimmed.empty() || trimmed.front() == '#') continue;
    ParseElement(Tokenize(trimmed, source_name, lines.line_number()), &p);
  }
  ResolveReferences(source_name, &p);
  if (p.graph.poses.empty()) ThrowIoError(source_name, 0, "", "no VERTEX_SE2");
  return std::move(p.graph);
}

graph::PoseGraph ReadG2o(const std::filesystem::path& path) {
  return ParseG2o(ReadTextFile(path), path.string());
}

std::string FormatG2o(const graph::PoseGraph& graph) {
  std::string out;
  for (const auto& [id, T] : graph.poses) {
    out += "VERTEX_SE2 " + std::to_string(id);
    AppendNumbers(&out, {T.x(), T.y(), T.yaw()});
    out.push_back('\n');
  }
  for (const auto& [id, p] : graph.points) {
    out += "VERTEX_XY " + std::to_string(id);
    AppendNumbers(&out, {p.x(), p.y()});
    out.push_back('\n');
  }
  for (int id : graph.fixed) out += "FIX " + std::to_string(id) + "\n";
  for (const graph::PoseEdge& e : graph.pose_edges) {
    out += "EDGE_SE2 " + std::to_string(e.from) + " " + std::to_string(e.to);
    const Eigen::Matrix3d& I = e.information;
    AppendNumbers(&out, {e.T_from_to.x(), e.T_from_to.y(), e.T_from_to.yaw(), I(0, 0), I(0, 1),
                         I(0, 2), I(1, 1), I(1, 2), I(2, 2)});
    out.push_back('\n');
  }
  for (const graph::PointEdge& e : graph.point_edges) {
    out += "EDGE_SE2_XY " + std::to_string(e.pose) + " " + std::to_string(e.point);
    const Eigen::Matrix2d& I = e.information;
    AppendNumbers(&out, {e.p_pose.x(), e.p_pose.y(), I(0, 0), I(0, 1), I(1, 1)});
    out.push_back('\n');
  }
  return out;
}

void WriteG2o(const std::filesystem::path& path, const graph::PoseGraph& graph) {
  WriteFileAtomically(path, FormatG2o(graph));
}

}  // namespace parkslam::io
