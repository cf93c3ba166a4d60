#ifndef PARKSLAM_IO_SCENARIO_YAML_H_
#define PARKSLAM_IO_SCENARIO_YAML_H_

// YAML files of sim::ScenarioConfig. The loader walks the structs'
// VisitFields() lists, so every field is written, read, and checked for
// unknown keys without code of its own. A file holds any subset of
//
//   world:    {name, hall: {min_x_m, ...}, rows: [{kind, origin_m: [x, y], ...}], ...}
//   route:    {approach_m: [[x, y], ...], loop_m, laps, finish_m, ...}
//   vehicle:  {wheelbase_m, ...}
//   sensors:  {odometry: {...}, slots: {...}, ids: {...}, tags: {...}}
//
// and is laid over a base configuration: keys present replace the base's
// values, a list present replaces the base's list whole (each element
// starting from the struct's defaults), missing keys keep the base's values.

#include <filesystem>
#include <string>

#include "parkslam/sim/scenario_config.h"

namespace parkslam::io {

// The whole configuration as block YAML; lists of points in flow style.
// Numbers are written to read back exactly.
std::string ScenarioToYaml(const sim::ScenarioConfig& config);

// `yaml_text` laid over `base`. Throws IoError naming source_name, the line
// and the dotted key path: "world.yaml:14: world.rows[2].widht_m: unknown
// key (did you mean 'width_m'?)", "...: route.laps: expected an integer,
// got 'two'". Does not validate; see LoadScenarioFile.
sim::ScenarioConfig ScenarioFromYaml(const std::string& yaml_text, const sim::ScenarioConfig& base,
                                     const std::string& source_name);

// The file laid over sim::DefaultScenario(), then validated: an invalid
// configuration throws IoError "file: <validator's message>".
sim::ScenarioConfig LoadScenarioFile(const std::filesystem::path& path);

// Applies one command-line assignment "key.path=value", the value a YAML
// scalar or flow node: "sensors.ids.confusion_rate=0.1", "route.laps=3",
// "world.hall={min_x_m: 0, min_y_m: 0, max_x_m: 40, max_y_m: 30}",
// "world.rows[1].count=12", "route.loop_m=[[4, 9], [70, 9]]". A mapping is
// laid over the current value; a list replaces it. Throws IoError
// "--set: unknown key 'sensors.ids.foo'" or "--set: route.laps: expected an
// integer, got 'x'". Does not validate.
void ApplyOverride(sim::ScenarioConfig* config, const std::string& assignment);

}  // namespace parkslam::io

#endif  // PARKSLAM_IO_SCENARIO_YAML_H_
