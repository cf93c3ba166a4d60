#ifndef PARKSLAM_OPTIONS_ALGORITHM_OPTIONS_H_
#define PARKSLAM_OPTIONS_ALGORITHM_OPTIONS_H_

// Every algorithm option a command may take from one file (`--config
// FILE.yaml`, io/options_yaml.h): the perception front end, the mapper, the
// localizer and the trace follower. Choices that are command-line flags (the
// detector, Max-Mixture or not, online or batch) are not in it.

#include <string>

#include "parkslam/control/path_follower.h"
#include "parkslam/localization/localizer.h"
#include "parkslam/mapping/mapper_options.h"
#include "parkslam/perception/front_end.h"

namespace parkslam {

struct AlgorithmOptions {
  perception::PerceptionOptions front_end;
  mapping::MapperOptions mapper;
  localization::LocalizerOptions localizer;
  control::PathFollowerOptions follower;

  // Each part's own check; the message names the field with its section:
  // "mapper.null_weight: must be in (0, 1]".
  bool IsValid(std::string* error) const;

  template <typename V>
  void VisitFields(V& v) {
    v("front_end", front_end);
    v("mapper", mapper);
    v("localizer", localizer);
    v("follower", follower);
  }
};

}  // namespace parkslam

#endif  // PARKSLAM_OPTIONS_ALGORITHM_OPTIONS_H_
