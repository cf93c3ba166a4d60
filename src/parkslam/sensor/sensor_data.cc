#include "parkslam/sensor/sensor_data.h"

namespace parkslam {

bool SlotIdReading::partial() const {
  bool any_read = false, any_unread = false;
  for (const DigitReading& d : digits) {
    (d.read() ? any_read : any_unread) = true;
  }
  return any_read && any_unread;
}

std::string SlotIdReading::best() const {
  std::string id;
  for (const DigitReading& d : digits) {
    id.push_back(d.read() ? d.hypotheses.front().digit : '?');
  }
  return id;
}

double SlotIdReading::confidence() const {
  double c = 1.0;
  bool any_read = false;
  for (const DigitReading& d : digits) {
    if (!d.read()) continue;
    any_read = true;
    c *= d.hypotheses.front().probability;
  }
  return any_read ? c : 0.0;
}

}  // namespace parkslam
