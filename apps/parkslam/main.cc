// parkslam: the command-line front end. Each subcommand reads files, calls
// the core libraries and writes files; nothing here holds an algorithm.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "commands.h"
#include "parkslam/io/io_error.h"

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
  parkslam::app::SetCommandLine(argc, argv);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const parkslam::io::IoError& e) {
    std::fprintf(stderr, "parkslam: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "parkslam: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
