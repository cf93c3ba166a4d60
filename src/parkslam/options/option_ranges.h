#ifndef PARKSLAM_OPTIONS_OPTION_RANGES_H_
#define PARKSLAM_OPTIONS_OPTION_RANGES_H_

// The plausible range of every number in the algorithm options (`--config
// FILE.yaml`, algorithm_options.h), in one table that the options check
// reads and docs/plausible_ranges.md shows (`--dump-ranges` prints it).
// A value beyond its range is a typo or a broken file, not a tuning: an
// unbounded "must be positive" let `front_end.tags.tag_size_m: 1e308`
// through, and the map then held no tag without a word.
//
// The ranges are plain bounds; relations between options (max_entrance_m
// above min_entrance_m) stay with each part's own IsValid(). A numeric
// option without a row is refused too, so that a new option cannot slip
// past the table (option_ranges_test walks every key).

#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "parkslam/options/algorithm_options.h"

namespace parkslam {

struct OptionRange {
  // The key as a file writes it ("front_end.tags.tag_size_m"); for a list
  // the range bounds each element.
  std::string_view key;
  double min = 0.0;
  double max = 0.0;
  bool min_open = false;  // "(min, ..." rather than "[min, ..."
  bool max_open = false;
  std::string_view unit;  // "" for none
  std::string_view why;

  bool Contains(double value) const;
  // "(0, 5] m".
  std::string Text() const;
};

// Every row, in the order of the options file.
std::span<const OptionRange> OptionRanges();

// The row bounding `key`. front_end.learned_slots.classical_options.* is
// the classical detector's block again and takes front_end.slots.*'s rows.
const OptionRange* FindOptionRange(std::string_view key);

// Every number in `options` with its key, in file order; a list's elements
// under the list's key.
std::vector<std::pair<std::string, double>> NumericOptions(const AlgorithmOptions& options);

// The first number outside its range (or without one), as
// "front_end.tags.tag_size_m: 1e+308 is outside the plausible range (0, 5] m".
bool CheckOptionRanges(const AlgorithmOptions& options, std::string* error);

// The table as docs/plausible_ranges.md holds it (Markdown).
std::string OptionRangesMarkdown();

}  // namespace parkslam

#endif  // PARKSLAM_OPTIONS_OPTION_RANGES_H_
