// libFuzzer target: the text the CLI's file handling trusts or refuses — an output folder's
// manifest (which names --force may remove) and text checked as UTF-8 before it reaches a JSON
// result. The bytes are a manifest's content and, as a whole, a piece of text.
//
// Findings (abort): a manifest name that is not a plain file name of the folder (a path, "..",
// the manifest or the lock, a control character), a name listed twice, a manifest that does not
// read back as the names it gave; printable() output that is not valid UTF-8 or holds a control
// character; and any disagreement between invalid_utf8_at and the JSON writer, which throws
// exactly for the text the check must refuse (otherwise a result would be lost at the end).
//
// Run: build-san/fuzz/hemicontact_output_fuzz fuzz/corpus-output -max_total_time=60
#include <hemicontact/core/text.hpp>
#include <hemicontact/output/output_dir.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

[[noreturn]] void finding(const char* what) {
  std::fprintf(stderr, "output_fuzz: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hemicontact;
  const std::string text(reinterpret_cast<const char*>(data), size);

  // The manifest: as given, and with the signature put in front (most inputs lack it).
  for (const std::string& m : {text, std::string(OUTPUT_MANIFEST_SIGNATURE) + "\n" + text}) {
    const auto names = parse_manifest(m);
    if (!names) continue;
    std::string again = std::string(OUTPUT_MANIFEST_SIGNATURE) + "\n";
    for (size_t i = 0; i < names->size(); ++i) {
      const std::string& n = (*names)[i];
      if (!plain_output_name(n) || n.find('/') != std::string::npos || n == "." || n == ".." ||
          n == OUTPUT_MANIFEST || n == OUTPUT_LOCK || n.find('\n') != std::string::npos ||
          n.find('\0') != std::string::npos)
        finding("a manifest name that is not a plain file name of the folder");
      if (std::find(names->begin(), names->begin() + static_cast<std::ptrdiff_t>(i), n) != names->begin() + static_cast<std::ptrdiff_t>(i))
        finding("a manifest name listed twice");
      again += n + "\n";
    }
    if (parse_manifest(again) != names) finding("a manifest does not read back as the names it gave");
  }

  // UTF-8: the check agrees with the JSON writer, and printable() is always writable and one line.
  const bool valid = invalid_utf8_at(text) == std::string::npos;
  bool writable = true;
  try {
    (void)nlohmann::json(text).dump();
  } catch (const nlohmann::json::type_error&) {
    writable = false;
  }
  if (valid != writable) finding("invalid_utf8_at disagrees with the JSON writer");
  const std::string shown = printable(text);
  if (invalid_utf8_at(shown) != std::string::npos) finding("printable() is not valid UTF-8");
  for (unsigned char c : shown)
    if (c < 0x20 || c == 0x7F) finding("printable() holds a control character");
  if (valid && std::none_of(text.begin(), text.end(), [](unsigned char c) { return c < 0x20 || c == 0x7F; }) &&
      shown != text)
    finding("printable() changed printable UTF-8 text");
  return 0;
}
