#include <hemicontact/output/output_dir.hpp>

#include <hemicontact/core/error.hpp>

#include <filesystem>
#include <fstream>
#include <system_error>

namespace hemicontact {

namespace fs = std::filesystem;

void prepare_output_dir(const std::string& dir, bool overwrite) {
  const std::string name = "--out '" + dir + "'";
  if (dir.empty()) input_error("--out: empty directory name");
  std::error_code ec;
  const fs::path p(dir);
  if (fs::exists(p, ec)) {
    if (!fs::is_directory(p, ec)) input_error(name + ": exists and is not a directory");
    if (!overwrite && fs::exists(p / "report.json", ec))
      input_error(name + " already holds results (report.json); pass --force to overwrite");
  } else {
    fs::create_directories(p, ec);
    if (ec) input_error(name + ": cannot create directory: " + ec.message());
  }
  // Probe with a real file: permission bits do not tell about read-only mounts, ACLs or root.
  const fs::path probe = p / ".hemicontact_write_probe";
  {
    std::ofstream f(probe);
    if (!f || !(f << "probe\n") || !f.flush()) {
      fs::remove(probe, ec);
      input_error(name + ": directory is not writable");
    }
  }
  fs::remove(probe, ec);
}

void write_text_file(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  if (!f) input_error("cannot write '" + path + "'");
  f << text;
  if (!f.flush()) input_error("cannot write '" + path + "' (disk full?)");
}

}  // namespace hemicontact
