#include "parkslam/io/options_yaml.h"

#include <algorithm>
#include <string>

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

namespace {

// The line of the key that a check's message begins with
// ("mapper.null_weight: ..."), 0 when the file does not give it (a default
// that another key's value made wrong).
int LineOfKeyIn(const YAML::Node& root, const std::string& message) {
  const std::size_t colon = message.find(": ");
  if (colon == std::string::npos) return 0;
  const std::string key = message.substr(0, colon);
  YAML::Node node = root;
  std::size_t begin = 0;
  while (begin <= key.size()) {
    const std::size_t dot = std::min(key.find('.', begin), key.size());
    if (!node.IsMap()) return 0;
    node = node[key.substr(begin, dot - begin)];
    if (!node.IsDefined()) return 0;
    begin = dot + 1;
  }
  return node.Mark().is_null() ? 0 : node.Mark().line + 1;
}

}  // namespace

AlgorithmOptions OptionsFromYaml(const std::string& yaml_text, const AlgorithmOptions& base,
                                 const std::string& source_name) {
  const YAML::Node root = yaml_util::LoadYaml(yaml_text, source_name);
  AlgorithmOptions options = base;
  if (!root.IsNull()) ReadValue(YamlReader(source_name, true), root, "", &options);
  std::string error;
  if (!options.IsValid(&error)) ThrowIoError(source_name, LineOfKeyIn(root, error), "", error);
  return options;
}

AlgorithmOptions LoadOptionsFile(const std::filesystem::path& path) {
  return OptionsFromYaml(ReadTextFile(path, kMaxYamlBytes), AlgorithmOptions{}, path.string());
}

}  // namespace parkslam::io
