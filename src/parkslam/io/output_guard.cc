#include "parkslam/io/output_guard.h"

#include <unistd.h>

#include <cerrno>
#include <system_error>

#include "parkslam/io/io_error.h"

namespace parkslam::io {
namespace {

namespace fs = std::filesystem;

// The path with links and dots resolved as far as it exists.
fs::path Resolved(const fs::path& path) {
  std::error_code ec;
  fs::path resolved = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? fs::absolute(path).lexically_normal() : resolved;
}

// Whether `inner` is `outer` or lies below it (resolved paths).
bool Within(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (o->empty()) continue;  // a trailing separator
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

[[noreturn]] void Refuse(const NamedPath& output, const std::string& what, const NamedPath& input) {
  throw IoError(output.name + " " + output.path.string() + ": " + what + " " + input.name + " " +
                input.path.string() + " (an output never replaces or goes into an input)");
}

// An output that stands where a device, FIFO or socket is: writing there
// would replace it (as root, `--out /dev/null` would replace the device).
void RefuseSpecialFile(const NamedPath& output) {
  std::error_code ec;
  const fs::file_status status = fs::status(output.path, ec);
  if (ec || !fs::exists(status)) return;
  if (!fs::is_regular_file(status) && !fs::is_directory(status)) {
    throw IoError(output.name + " " + output.path.string() +
                  ": exists and is not a plain file or a folder (a device, FIFO or socket); an "
                  "output never replaces one");
  }
}

// Two outputs of one command that name the same file: the second write
// would replace the first.
void RefuseSharedOutputs(const std::vector<NamedPath>& outputs) {
  for (size_t i = 0; i < outputs.size(); ++i) {
    if (outputs[i].path.empty()) continue;
    const fs::path a = Resolved(outputs[i].path);
    for (size_t j = i + 1; j < outputs.size(); ++j) {
      if (outputs[j].path.empty()) continue;
      std::error_code ec;
      if (a == Resolved(outputs[j].path) || fs::equivalent(outputs[i].path, outputs[j].path, ec)) {
        throw IoError(outputs[j].name + " " + outputs[j].path.string() + ": is also " +
                      outputs[i].name + " " + outputs[i].path.string() +
                      " (each output of a command goes to a file of its own)");
      }
    }
  }
}

// A file output that cannot be written where it is asked for, refused
// before the command writes anything: a folder, a path ending in "/"
// (`--out o.x/`), or a place below a file or in a read-only folder.
void RefuseUnwritableFile(const NamedPath& output) {
  const std::string spelled = output.path.string();
  const auto refuse = [&](const std::string& why) {
    throw IoError(output.name + " " + spelled + ": " + why);
  };
  if (spelled.back() == '/') refuse("names a folder (it ends in /); this output is a file");
  std::error_code ec;
  if (fs::is_directory(output.path, ec)) refuse("is a folder, not a file");
  // The nearest folder above it that exists must be a folder, and writable.
  fs::path above = fs::absolute(output.path, ec).parent_path();
  while (!above.empty() && !fs::exists(above, ec) && above != above.parent_path()) {
    above = above.parent_path();
  }
  if (above.empty()) return;
  if (!fs::is_directory(above, ec)) refuse("cannot be made: " + above.string() + " is a file");
  if (::access(above.c_str(), W_OK) != 0) {
    refuse("cannot be written: " + above.string() + ": " + std::generic_category().message(errno));
  }
}

}  // namespace

void CheckOutputsSpareInputs(const std::vector<NamedPath>& outputs,
                             const std::vector<NamedPath>& inputs) {
  RefuseSharedOutputs(outputs);
  for (const NamedPath& output : outputs) {
    if (output.path.empty()) continue;
    RefuseSpecialFile(output);
    const fs::path out = Resolved(output.path);
    std::error_code ec;
    const bool out_exists = fs::exists(output.path, ec);
    const bool out_is_folder = fs::is_directory(output.path, ec);
    for (const NamedPath& input : inputs) {
      if (input.path.empty() || !fs::exists(input.path, ec)) continue;
      const fs::path in = Resolved(input.path);
      // Equal once resolved (a folder not made yet, then "..", names an
      // existing file), or the same file by identity (a hard link).
      if (out == in || (out_exists && fs::equivalent(output.path, input.path, ec))) {
        Refuse(output, "is the input", input);
      }
      if (fs::is_directory(input.path, ec) && Within(out, in))
        Refuse(output, "lies inside the input", input);
      if (out_is_folder && Within(in, out))
        Refuse(output, "is a folder that holds the input", input);
    }
    if (!output.folder) RefuseUnwritableFile(output);
  }
}

}  // namespace parkslam::io
