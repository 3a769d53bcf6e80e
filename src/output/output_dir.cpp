#include <hemicontact/output/output_dir.hpp>

#include <hemicontact/core/error.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

namespace hemicontact {

namespace fs = std::filesystem;

namespace {

// A name the manifest may list: a plain file name in the folder itself. Anything else (a path, "..",
// the manifest) is never removed or trusted, whoever edited the manifest.
bool plain_name(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name != OUTPUT_MANIFEST &&
         name.find('/') == std::string::npos && name.find('\0') == std::string::npos;
}

}  // namespace

std::vector<std::string> output_files(const std::string& dir) {
  std::vector<std::string> names;
  std::ifstream in(fs::path(dir) / OUTPUT_MANIFEST);
  for (std::string line; std::getline(in, line);)
    if (plain_name(line) && std::find(names.begin(), names.end(), line) == names.end()) names.push_back(line);
  return names;
}

void prepare_output_dir(const std::string& dir, bool overwrite, const std::vector<std::string>& will_write) {
  const std::string name = "--out '" + dir + "'";
  if (dir.empty()) input_error("--out: empty directory name");
  std::error_code ec;
  const fs::path p(dir);
  const fs::path manifest = p / OUTPUT_MANIFEST;
  if (fs::exists(p, ec)) {
    if (!fs::is_directory(p, ec)) input_error(name + ": exists and is not a directory");
    // Results: a report.json, or files an earlier run listed (an interrupted run leaves a manifest
    // with the files it got to write; one that failed before writing any left it empty).
    std::vector<std::string> ours = output_files(dir);
    // A result set of a version before the manifest: its marker file (report.json, or a study's
    // JSON) says an earlier run of the tool wrote there, and then the names this run writes are
    // the names that run wrote.
    if (!fs::exists(manifest, ec))
      for (const char* marker : {"report.json", "convergence.json", "minima.json"})
        if (fs::exists(p / marker, ec)) {
          for (const std::string& f : will_write)
            if (fs::exists(p / f, ec)) ours.push_back(f);
          break;
        }
    const bool has_results = fs::exists(p / "report.json", ec) || !ours.empty();
    if (!overwrite && has_results)
      input_error(name + " already holds results (" +
                  (fs::exists(p / "report.json", ec) ? std::string("report.json")
                                                     : ours.front() + ", listed in " + OUTPUT_MANIFEST) +
                  "); pass --force to replace them");
    // The files this run will write must be ours to replace: a user's own file of the same name
    // is never overwritten, not even with --force.
    for (const std::string& f : will_write)
      if (fs::exists(p / f, ec) && f != "report.json" && std::find(ours.begin(), ours.end(), f) == ours.end())
        input_error(name + ": '" + f + "' exists and was not written by hemicontact (it is not listed in " +
                    OUTPUT_MANIFEST + "); move it away or choose another --out");
    if (overwrite) {
      // --force replaces the previous result set as a whole: exactly the files it listed.
      for (const std::string& f : ours)
        if (fs::is_regular_file(fs::symlink_status(p / f, ec))) fs::remove(p / f, ec);
      if (has_results) fs::remove(p / "report.json", ec);
    }
  } else {
    fs::create_directories(p, ec);
    if (ec) input_error(name + ": cannot create directory: " + ec.message());
  }
  // A fresh, empty manifest; writing it also proves that the folder is writable (permission bits
  // do not tell about read-only mounts, ACLs or root).
  std::ofstream f(manifest, std::ios::trunc);
  if (!f || !f.flush()) input_error(name + ": directory is not writable");
}

void record_output_file(const std::string& path) {
  const fs::path p(path);
  const fs::path manifest = p.parent_path().empty() ? fs::path(OUTPUT_MANIFEST) : p.parent_path() / OUTPUT_MANIFEST;
  std::error_code ec;
  if (!fs::exists(manifest, ec)) return;  // not a prepared output folder: nothing to record
  const std::string file = p.filename().string();
  const std::vector<std::string> listed = output_files(manifest.parent_path().string());
  if (!plain_name(file) || std::find(listed.begin(), listed.end(), file) != listed.end()) return;
  std::ofstream(manifest, std::ios::app) << file << '\n';
}

void write_text_file(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  if (!f) input_error("cannot write '" + path + "'");
  f << text;
  if (!f.flush()) input_error("cannot write '" + path + "' (disk full?)");
  f.close();
  record_output_file(path);
}

}  // namespace hemicontact
