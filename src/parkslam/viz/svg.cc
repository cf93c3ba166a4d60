#include "parkslam/viz/svg.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace parkslam::viz {
namespace {

void AppendAttribute(std::string* out, std::string_view name, std::string_view value) {
  out->append(" ").append(name).append("=\"").append(XmlEscape(value)).append("\"");
}

void AppendNumber(std::string* out, std::string_view name, double value) {
  AppendAttribute(out, name, FormatPx(value));
}

std::string StyleAttributes(const SvgStyle& style) {
  std::string out;
  if (!style.stroke.empty()) AppendAttribute(&out, "stroke", style.stroke);
  if (!style.fill.empty()) AppendAttribute(&out, "fill", style.fill);
  if (style.width_px > 0.0) AppendNumber(&out, "stroke-width", style.width_px);
  if (!style.dash.empty()) AppendAttribute(&out, "stroke-dasharray", style.dash);
  if (style.opacity < 1.0) {
    AppendAttribute(&out, "opacity", FormatFixed(style.opacity, 2));
  }
  if (style.font_size_px > 0.0) {
    AppendNumber(&out, "font-size", style.font_size_px);
  }
  if (!style.text_anchor.empty()) {
    AppendAttribute(&out, "text-anchor", style.text_anchor);
  }
  if (!style.font_weight.empty()) {
    AppendAttribute(&out, "font-weight", style.font_weight);
  }
  return out;
}

}  // namespace

std::string FormatFixed(double value, int decimals) {
  if (!std::isfinite(value)) return "0";
  const double scale = std::pow(10.0, decimals);
  double rounded = std::round(value * scale) / scale;
  if (rounded == 0.0) rounded = 0.0;  // no "-0"
  char buffer[64];
  const auto [end, error] =
      std::to_chars(buffer, buffer + sizeof(buffer), rounded, std::chars_format::fixed, decimals);
  if (error != std::errc()) return "0";
  std::string out(buffer, end);
  // Trailing zeros of the fraction, then a bare point.
  if (out.find('.') != std::string::npos) {
    while (out.back() == '0') out.pop_back();
    if (out.back() == '.') out.pop_back();
  }
  return out;
}

std::string XmlEscape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string FormatPx(double value) { return FormatFixed(value, 1); }

SvgCanvas::SvgCanvas(const Eigen::Vector2d& min_map_m, const Eigen::Vector2d& max_map_m,
                     double pixels_per_m, double margin_px)
    : min_map_m_(min_map_m),
      max_map_m_(max_map_m),
      pixels_per_m_(pixels_per_m),
      margin_px_(margin_px) {
  if (!(pixels_per_m > 0.0) || !(margin_px >= 0.0)) {
    throw std::invalid_argument("SvgCanvas: needs pixels_per_m > 0 and margin_px >= 0");
  }
  if (!(max_map_m.x() >= min_map_m.x()) || !(max_map_m.y() >= min_map_m.y())) {
    throw std::invalid_argument("SvgCanvas: the box's max is below its min");
  }
  const Eigen::Vector2d size_px = (max_map_m - min_map_m) * pixels_per_m;
  width_px_ = std::ceil(size_px.x() + 2.0 * margin_px);
  height_px_ = std::ceil(size_px.y() + 2.0 * margin_px);
}

Eigen::Vector2d SvgCanvas::ToPixel(const Eigen::Vector2d& p_map) const {
  return {margin_px_ + (p_map.x() - min_map_m_.x()) * pixels_per_m_,
          margin_px_ + (max_map_m_.y() - p_map.y()) * pixels_per_m_};
}

Eigen::Vector2d SvgCanvas::ToMap(const Eigen::Vector2d& p_px) const {
  return {min_map_m_.x() + (p_px.x() - margin_px_) / pixels_per_m_,
          max_map_m_.y() - (p_px.y() - margin_px_) / pixels_per_m_};
}

std::string SvgCanvas::PointList(const std::vector<Eigen::Vector2d>& points_map) const {
  std::string out;
  out.reserve(points_map.size() * 12);
  for (const Eigen::Vector2d& p_map : points_map) {
    const Eigen::Vector2d p_px = ToPixel(p_map);
    if (!out.empty()) out += ' ';
    out += FormatPx(p_px.x());
    out += ',';
    out += FormatPx(p_px.y());
  }
  return out;
}

void SvgCanvas::Polygon(const std::vector<Eigen::Vector2d>& points_map, const SvgStyle& style) {
  body_ += "<polygon points=\"" + PointList(points_map) + "\"" + StyleAttributes(style) + "/>\n";
}

void SvgCanvas::Polyline(const std::vector<Eigen::Vector2d>& points_map, const SvgStyle& style) {
  SvgStyle open_style = style;
  if (open_style.fill.empty()) open_style.fill = "none";
  body_ +=
      "<polyline points=\"" + PointList(points_map) + "\"" + StyleAttributes(open_style) + "/>\n";
}

void SvgCanvas::Line(const Eigen::Vector2d& from_map, const Eigen::Vector2d& to_map,
                     const SvgStyle& style) {
  const Eigen::Vector2d from_px = ToPixel(from_map);
  const Eigen::Vector2d to_px = ToPixel(to_map);
  body_ += "<line";
  AppendNumber(&body_, "x1", from_px.x());
  AppendNumber(&body_, "y1", from_px.y());
  AppendNumber(&body_, "x2", to_px.x());
  AppendNumber(&body_, "y2", to_px.y());
  body_ += StyleAttributes(style) + "/>\n";
}

void SvgCanvas::Rect(const Eigen::Vector2d& corner_a_map, const Eigen::Vector2d& corner_b_map,
                     const SvgStyle& style) {
  const Eigen::Vector2d a_px = ToPixel(corner_a_map);
  const Eigen::Vector2d b_px = ToPixel(corner_b_map);
  const Eigen::Vector2d min_px = a_px.cwiseMin(b_px);
  const Eigen::Vector2d size_px = (a_px - b_px).cwiseAbs();
  body_ += "<rect";
  AppendNumber(&body_, "x", min_px.x());
  AppendNumber(&body_, "y", min_px.y());
  AppendNumber(&body_, "width", size_px.x());
  AppendNumber(&body_, "height", size_px.y());
  body_ += StyleAttributes(style) + "/>\n";
}

void SvgCanvas::Circle(const Eigen::Vector2d& center_map, double radius_px, const SvgStyle& style) {
  const Eigen::Vector2d center_px = ToPixel(center_map);
  body_ += "<circle";
  AppendNumber(&body_, "cx", center_px.x());
  AppendNumber(&body_, "cy", center_px.y());
  AppendNumber(&body_, "r", radius_px);
  body_ += StyleAttributes(style) + "/>\n";
}

void SvgCanvas::Text(const Eigen::Vector2d& anchor_map, std::string_view text,
                     const SvgStyle& style, double rotation_deg) {
  const Eigen::Vector2d anchor_px = ToPixel(anchor_map);
  body_ += "<text";
  AppendNumber(&body_, "x", anchor_px.x());
  AppendNumber(&body_, "y", anchor_px.y());
  if (style.center_vertically) body_ += " dy=\".35em\"";
  if (rotation_deg != 0.0) {
    body_ += " transform=\"rotate(" + FormatPx(rotation_deg) + " " + FormatPx(anchor_px.x()) + " " +
             FormatPx(anchor_px.y()) + ")\"";
  }
  body_ += StyleAttributes(style) + ">" + XmlEscape(text) + "</text>\n";
}

void SvgCanvas::BeginGroup(const SvgStyle& style, std::string_view id) {
  body_ += "<g";
  if (!id.empty()) AppendAttribute(&body_, "id", id);
  body_ += StyleAttributes(style) + ">\n";
  ++open_groups_;
}

void SvgCanvas::EndGroup() {
  if (open_groups_ == 0) {
    throw std::logic_error("SvgCanvas::EndGroup: no group is open");
  }
  body_ += "</g>\n";
  --open_groups_;
}

std::string SvgCanvas::Finish() const {
  const std::string width = FormatPx(width_px_);
  const std::string height = FormatPx(height_px_);
  std::string document;
  document.reserve(body_.size() + 400);
  document += "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n";
  document += "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" + width +
              "\" height=\"" + height + "\" viewBox=\"0 0 " + width + " " + height +
              "\" font-family=\"sans-serif\">\n";
  document += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  document += body_;
  for (int i = 0; i < open_groups_; ++i) document += "</g>\n";
  document += "</svg>\n";
  return document;
}

}  // namespace parkslam::viz
