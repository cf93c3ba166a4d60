#ifndef PARKSLAM_COMMON_FIELD_CHECKER_H_
#define PARKSLAM_COMMON_FIELD_CHECKER_H_

// The checks of every validator (scenarios, plans, algorithm options), each
// failure named by its field, "field: what" (the first one is kept). A
// nested part's message gets the part's key in front: "pairing.min_entrance_m:
// must be ...", so that a message names the key as a file writes it.

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <string>

#include "parkslam/common/plausible_ranges.h"

namespace parkslam {

// A limit as written in messages: "1.5", "10", "1e+05".
inline std::string Limit(double limit) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", limit);
  return buffer;
}

// Collects the first failed check with the name of its field. The ranges
// of physical quantities are those of common/plausible_ranges.h. Every
// check fails for NaN.
class FieldChecker {
 public:
  explicit FieldChecker(std::string* error) : error_(error) {}

  bool ok() const { return ok_; }

  void Require(bool condition, const std::string& field, const std::string& what) {
    if (!ok_ || condition) return;
    ok_ = false;
    if (error_ != nullptr) *error_ = field + ": " + what;
  }
  // A check made elsewhere whose message already names the field.
  void Require(bool condition, const std::string& message) {
    if (!ok_ || condition) return;
    ok_ = false;
    if (error_ != nullptr) *error_ = message;
  }
  void Rate(double value, const std::string& field) {
    Require(std::isfinite(value) && value >= 0.0 && value <= 1.0, field,
            "must be a probability in [0, 1]");
  }
  void Positive(double value, const std::string& field) {
    Require(std::isfinite(value) && value > 0.0, field, "must be positive");
  }
  void NonNegative(double value, const std::string& field) {
    Require(std::isfinite(value) && value >= 0.0, field, "must be non-negative");
  }
  // value >= min (a count, say: "must be at least 1").
  void AtLeast(double value, double min, const std::string& field) {
    Require(value >= min, field, "must be at least " + Limit(min));
  }
  // value in (min, max); unit as for InRange.
  void Between(double value, double min, double max, const std::string& field, const char* unit) {
    if (!ok_ || (value > min && value < max)) return;
    Require(false, field, "must be in (" + Limit(min) + ", " + Limit(max) + ")" + Unit(unit));
  }
  // A nested part with its own IsValid(std::string*): its message, with
  // the part's key in front.
  template <typename T>
  void Part(const T& part, const std::string& field) {
    if (!ok_) return;
    std::string message;
    if (!part.IsValid(&message)) Require(false, field + "." + message);
  }
  // value in [min, max]; unit after the limits in the message ("" for none).
  void InRange(double value, double min, double max, const std::string& field, const char* unit) {
    if (!ok_ || (value >= min && value <= max)) return;
    Require(false, field, "must be in [" + Limit(min) + ", " + Limit(max) + "]" + Unit(unit));
  }
  // value in (0, max].
  void PositiveAtMost(double value, double max, const std::string& field, const char* unit) {
    if (!ok_ || (value > 0.0 && value <= max)) return;
    Require(false, field, "must be in (0, " + Limit(max) + "]" + Unit(unit));
  }
  // |value| <= max_abs.
  void Magnitude(double value, double max_abs, const std::string& field, const char* unit) {
    if (!ok_ || std::abs(value) <= max_abs) return;
    Require(false, field, "must be at most " + Limit(max_abs) + Unit(unit) + " in magnitude");
  }
  void Point(const Eigen::Vector2d& p, const std::string& field) {
    Magnitude(p.x(), kMaxCoordinate_m, field, "m");
    Magnitude(p.y(), kMaxCoordinate_m, field, "m");
  }

 private:
  static std::string Unit(const char* unit) {
    return *unit == '\0' ? std::string() : std::string(" ") + unit;
  }

  std::string* error_;
  bool ok_ = true;
};

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_FIELD_CHECKER_H_
