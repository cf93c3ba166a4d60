// parkslam: the command-line front end. Each subcommand reads files, calls
// the core libraries and writes files; nothing here holds an algorithm.

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <new>

#include "commands.h"
#include "interruption.h"
#include "parkslam/io/io_error.h"

namespace {

// Every number option of every command takes finite values only: NaN passes
// every range check (`--image-rate-hz nan` looped for ever) and 1e999 is
// infinity. Ranges stay each option's own.
void RefuseNonFiniteNumbers(CLI::App* app) {
  const CLI::Validator finite(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end != text.c_str() && !std::isfinite(value)) {
          return "a finite number is needed, not " + text;
        }
        return "";
      },
      "");
  // An empty value (`--out ''`, `--init ''`) is a slip of the shell, never a
  // choice: it would reach the command as "no file" or "the default".
  const CLI::Validator not_empty(
      [](std::string& text) -> std::string {
        return text.empty() ? "an empty value is not one (give the value, or leave the option "
                              "out)"
                            : "";
      },
      "");
  for (CLI::Option* option : app->get_options()) {
    if (option->get_type_name().rfind("FLOAT", 0) == 0) option->check(finite);
    if (!option->get_type_name().empty() && option->get_type_name() != "BOOLEAN") {
      option->check(not_empty);
    }
  }
  for (CLI::App* command : app->get_subcommands([](CLI::App*) { return true; })) {
    RefuseNonFiniteNumbers(command);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "parkslam: vision-based semantic mapping and localization for autonomous indoor "
      "parking.\nRun `parkslam demo --out DIR` for the whole pipeline on the built-in lot."};
  app.set_version_flag("--version", parkslam::app::kVersion);
  app.require_subcommand(1);
  parkslam::app::AddSimulateCommand(app);
  parkslam::app::AddOdometryCommand(app);
  parkslam::app::AddEvalTrajCommand(app);
  parkslam::app::AddMapCommand(app);
  parkslam::app::AddUpdateMapCommand(app);
  parkslam::app::AddEvalMapCommand(app);
  parkslam::app::AddRenderCommand(app);
  parkslam::app::AddPlanFromMapCommand(app);
  parkslam::app::AddLocalizeCommand(app);
  parkslam::app::AddFollowCommand(app);
  parkslam::app::AddTopviewCommand(app);
  parkslam::app::AddTagsCommand(app);
  parkslam::app::AddDetectCommand(app);
  parkslam::app::AddEvalDetectCommand(app);
  parkslam::app::AddMakeTrainingSetCommand(app);
  parkslam::app::AddDemoCommand(app);
  parkslam::app::AddReportCommand(app);
  parkslam::app::AddCheckDatasetCommand(app);
  parkslam::app::AddSolveGraphCommand(app);
  parkslam::app::AddMakeGraphCommand(app);
#ifdef PARKSLAM_HAVE_ROSBAG
  parkslam::app::AddImportRosbagCommand(app);
  parkslam::app::AddExportRosbagCommand(app);
#endif
  RefuseNonFiniteNumbers(&app);
  parkslam::app::SetCommandLine(argc, argv);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const parkslam::app::Interrupted& e) {
    std::fprintf(stderr, "parkslam: %s\n", e.what());
    return 128 + e.signal_number();
  } catch (const parkslam::io::IoError& e) {
    std::fprintf(stderr, "parkslam: error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr,
                 "parkslam: error: out of memory (an input or an option asks for more than this "
                 "machine has; docs/plausible_ranges.md gives what each may be)\n");
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    std::fprintf(stderr, "parkslam: error: %s: %s\n", e.path1().string().c_str(),
                 e.code().message().c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "parkslam: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
