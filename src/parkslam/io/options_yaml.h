#ifndef PARKSLAM_IO_OPTIONS_YAML_H_
#define PARKSLAM_IO_OPTIONS_YAML_H_

// The algorithm options file of `--config FILE.yaml`
// (options/algorithm_options.h): sections front_end, mapper, localizer and
// follower, each a partial overlay on the defaults, read as strictly as the
// scenario files: an unknown key or a bad value is an error naming the file,
// the line and the key ("my.yaml:7: mapper.null_wieght: unknown key (did you
// mean 'null_weight'?)"). `--dump-config` prints every option with its
// default (OptionsToYaml). Read with the scenario files' field walker
// (visit_yaml.h); its own target, parkslam_options_yaml, so that the file
// formats do not link the experiment harness.

#include <filesystem>
#include <string>

#include "parkslam/options/algorithm_options.h"

namespace parkslam::io {

std::string OptionsToYaml(const AlgorithmOptions& options);

// Overlays `yaml_text` onto `base`; an empty text changes nothing. Throws
// IoError naming source_name, the line and the key, also when the result
// fails AlgorithmOptions::IsValid.
AlgorithmOptions OptionsFromYaml(const std::string& yaml_text, const AlgorithmOptions& base,
                                 const std::string& source_name);

// The defaults overlaid with the file.
AlgorithmOptions LoadOptionsFile(const std::filesystem::path& path);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_OPTIONS_YAML_H_
