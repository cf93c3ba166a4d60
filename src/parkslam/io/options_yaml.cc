#include "parkslam/io/options_yaml.h"

#include "parkslam/io/atomic_file.h"
#include "parkslam/io/io_error.h"
#include "parkslam/io/visit_yaml.h"
#include "parkslam/io/yaml_util.h"

namespace parkslam::io {

using visit_yaml::ReadValue;
using visit_yaml::WriteFields;
using yaml_util::YamlReader;

std::string OptionsToYaml(const AlgorithmOptions& options) {
  std::string out =
      "# parkslam algorithm options (--config FILE.yaml): front end, mapper, localizer,\n"
      "# follower. Give only the keys you change; units are in the key names.\n";
  AlgorithmOptions copy = options;  // VisitFields() is not const
  WriteFields(copy, 0, &out);
  return out;
}

AlgorithmOptions OptionsFromYaml(const std::string& yaml_text, const AlgorithmOptions& base,
                                 const std::string& source_name) {
  const YAML::Node root = yaml_util::LoadYaml(yaml_text, source_name);
  AlgorithmOptions options = base;
  if (!root.IsNull()) ReadValue(YamlReader(source_name, true), root, "", &options);
  std::string error;
  if (!options.IsValid(&error)) ThrowIoError(source_name, 0, "", error);
  return options;
}

AlgorithmOptions LoadOptionsFile(const std::filesystem::path& path) {
  return OptionsFromYaml(ReadTextFile(path, kMaxYamlBytes), AlgorithmOptions{}, path.string());
}

}  // namespace parkslam::io
