#ifndef PARKSLAM_VIZ_SVG_H_
#define PARKSLAM_VIZ_SVG_H_

// A small SVG 1.1 writer for top-down pictures of the map frame. Points are
// given in map coordinates (metres, y up) and drawn with y down; numbers are
// written to 0.1 px. The canvas only builds a string: it never opens files.

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

namespace parkslam::viz {

// Presentation attributes. An empty string or a zero size is not written,
// so the element inherits it from its group (or takes the SVG default).
struct SvgStyle {
  std::string stroke = "";  // "#333333", "orange", "none"
  std::string fill = "";
  double width_px = 0.0;  // stroke width
  std::string dash = "";  // stroke-dasharray in px, e.g. "4 3"
  double opacity = 1.0;
  double font_size_px = 0.0;
  std::string text_anchor = "";  // "start", "middle" or "end"
  std::string font_weight = "";  // "bold"
  // Text only: shift the baseline so the anchor sits at the text's middle.
  bool center_vertically = false;
};

// Escapes the five XML special characters.
std::string XmlEscape(std::string_view text);

// A number rounded to `decimals` places, without trailing zeros ("12.3",
// "-4", "0").
std::string FormatFixed(double value, int decimals);

// A pixel coordinate or size: FormatFixed(value, 1).
std::string FormatPx(double value);

class SvgCanvas {
 public:
  // The map-frame box [min_map_m, max_map_m] fills the picture at
  // pixels_per_m, inside a blank border of margin_px on every side. Throws
  // std::invalid_argument for a non-positive scale, a negative margin or an
  // inverted box.
  SvgCanvas(const Eigen::Vector2d& min_map_m, const Eigen::Vector2d& max_map_m, double pixels_per_m,
            double margin_px = 20.0);

  double width_px() const { return width_px_; }
  double height_px() const { return height_px_; }
  double pixels_per_m() const { return pixels_per_m_; }

  // Map frame (y up) to picture pixels (y down) and back.
  Eigen::Vector2d ToPixel(const Eigen::Vector2d& p_map) const;
  Eigen::Vector2d ToMap(const Eigen::Vector2d& p_px) const;

  void Polygon(const std::vector<Eigen::Vector2d>& points_map, const SvgStyle& style);
  // An open polyline; its fill is "none" unless the style sets one.
  void Polyline(const std::vector<Eigen::Vector2d>& points_map, const SvgStyle& style);
  void Line(const Eigen::Vector2d& from_map, const Eigen::Vector2d& to_map, const SvgStyle& style);
  // The axis-aligned rectangle with these two opposite corners.
  void Rect(const Eigen::Vector2d& corner_a_map, const Eigen::Vector2d& corner_b_map,
            const SvgStyle& style);
  void Circle(const Eigen::Vector2d& center_map, double radius_px, const SvgStyle& style);
  // Text anchored at a map point, turned clockwise on screen by rotation_deg.
  void Text(const Eigen::Vector2d& anchor_map, std::string_view text, const SvgStyle& style,
            double rotation_deg = 0.0);

  // A <g> whose style its children inherit; groups nest. EndGroup without an
  // open group throws std::logic_error.
  void BeginGroup(const SvgStyle& style = {}, std::string_view id = {});
  void EndGroup();

  // The complete standalone document: XML declaration, white background, the
  // elements drawn so far, and a closing tag for every group still open.
  std::string Finish() const;

 private:
  std::string PointList(const std::vector<Eigen::Vector2d>& points_map) const;

  Eigen::Vector2d min_map_m_;
  Eigen::Vector2d max_map_m_;
  double pixels_per_m_;
  double margin_px_;
  double width_px_;
  double height_px_;
  std::string body_;
  int open_groups_ = 0;
};

}  // namespace parkslam::viz

#endif  // PARKSLAM_VIZ_SVG_H_
