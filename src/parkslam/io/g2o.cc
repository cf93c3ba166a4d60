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

// A two-component EDGE_SE2_MIXTURE line has 29 values.
constexpr std::size_t kMaxFields = 32;

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
  int null_line = 0;               // the first EDGE_SE2_MIXTURE line
  std::map<int, int> vertex_line;  // id -> line that defined it
  std::vector<int> pose_edge_lines, point_edge_lines, fix_lines;
  std::vector<int> fix_ids;
};

bool Near(double a, double b) {
  return std::abs(a - b) <= 1e-9 * (1.0 + std::abs(a) + std::abs(b));
}

// EDGE_SE2_MIXTURE a b 2  EDGE_SE2 w a b dx dy dtheta I11 I12 I13 I22 I23 I33  EDGE_SE2 ...
// (Agarwal and Olson's Max-Mixture plugin for g2o): read where it is a
// closure and its null hypothesis, the same measurement between the same
// vertices, one component's information a scale s < 1 of the other's. The
// closure enters as an EDGE_SE2 with the stronger component; weight and
// scale become the graph's file_null, the same for every mixture line.
void ParseMixture(const Line& line, G2oParse* p) {
  line.ExpectCount(29);
  const int from = line.Id(0, "a"), to = line.Id(1, "b");
  if (from == to) line.Fail("b", "an edge from a vertex to itself");
  if (text::ParseInt64(line.fields[2]) != 2) {
    line.Fail("components", "this reader takes two components (a closure and its null), found " +
                                text::Quoted(line.fields[2]));
  }
  struct Component {
    double weight;
    SE2 measured;
    Eigen::Matrix3d information;
  };
  std::array<Component, 2> c;
  for (int k = 0; k < 2; ++k) {
    const std::size_t at = 3 + 13 * static_cast<std::size_t>(k);
    if (line.fields[at] != "EDGE_SE2") {
      line.Fail("component", "expected EDGE_SE2, found " + text::Quoted(line.fields[at]));
    }
    c[k].weight = line.Number(at + 1, "w", 1e12, "");
    if (!(c[k].weight > 0.0)) line.Fail("w", "a component's weight must be positive");
    if (line.Id(at + 2, "a") != from || line.Id(at + 3, "b") != to) {
      line.Fail("component", "both components must join vertices " + std::to_string(from) +
                                 " and " + std::to_string(to));
    }
    c[k].measured = SE2(line.Number(at + 4, "dx", kMaxCoordinate_m, "m"),
                        line.Number(at + 5, "dy", kMaxCoordinate_m, "m"),
                        line.Number(at + 6, "dtheta", kMaxAngle_rad, "rad"));
    c[k].information = Information<3>(line, at + 7);
  }
  const int own = c[0].information.trace() >= c[1].information.trace() ? 0 : 1;
  const Component& closure = c[own];
  const Component& null = c[1 - own];
  if (!Near(closure.measured.x(), null.measured.x()) ||
      !Near(closure.measured.y(), null.measured.y()) ||
      !Near(closure.measured.yaw(), null.measured.yaw())) {
    line.Fail("component",
              "the two components measure different poses (this reader takes a "
              "closure and its null hypothesis)");
  }
  const double scale = null.information.trace() / closure.information.trace();
  if (!(scale < 1.0) || !null.information.isApprox(scale * closure.information, 1e-6)) {
    line.Fail("I", "the null's information is not a scale below 1 of the closure's");
  }
  const graph::NullHypothesis file_null{null.weight / closure.weight, scale};
  if (!(file_null.weight <= 1.0)) {
    line.Fail("w", "the null's weight exceeds the closure's");
  }
  if (p->graph.file_null) {
    if (!Near(p->graph.file_null->weight, file_null.weight) ||
        std::abs(p->graph.file_null->information_scale / file_null.information_scale - 1.0) >
            1e-6) {
      line.Fail("component", "a null hypothesis other than line " + std::to_string(p->null_line) +
                                 "'s (this reader takes one per file)");
    }
  } else {
    p->graph.file_null = file_null;
    p->null_line = line.number;
  }
  p->graph.pose_edges.push_back({from, to, closure.measured, closure.information});
  p->pose_edge_lines.push_back(line.number);
}

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
  } else if (line.type == "EDGE_SE2_MIXTURE") {
    ParseMixture(line, p);
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
    if (line.count > kMaxFields) {
      line.Fail("", "more than " + std::to_string(kMaxFields) + " ids on one line");
    }
    for (std::size_t i = 0; i < line.count; ++i) {
      p->fix_ids.push_back(line.Id(i, "id"));
      p->fix_lines.push_back(line.number);
    }
  } else {
    line.Fail("",
              "unknown element type (this reader takes VERTEX_SE2, VERTEX_XY, EDGE_SE2, "
              "EDGE_SE2_MIXTURE, EDGE_SE2_XY and FIX)");
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
  if (p.graph.poses.size() > kMaxG2oPoses) {
    ThrowIoError(source_name, 0, "",
                 std::to_string(p.graph.poses.size()) + " poses; solve-graph takes at most " +
                     std::to_string(kMaxG2oPoses) +
                     " (docs/plausible_ranges.md, \"Input sizes\": memory and time grow faster "
                     "than the graph)");
  }
  const std::size_t edges = p.graph.pose_edges.size() + p.graph.point_edges.size();
  if (edges > kMaxG2oEdges) {
    std::string message = std::to_string(edges);
    message.append(" edges; solve-graph takes at most ")
        .append(std::to_string(kMaxG2oEdges))
        .append(" (docs/plausible_ranges.md, \"Input sizes\")");
    ThrowIoError(source_name, 0, "", message);
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
