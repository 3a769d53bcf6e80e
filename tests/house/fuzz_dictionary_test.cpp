// The scene fuzzer's dictionary (fuzz/scene.dict, written by fuzz/make_corpus.py) holds every part
// of every scene key the schema documents (docs/scene-format.md, generated from the schema): a key
// added to the schema and not to the dictionary is one the fuzzer reaches only by chance.
#include "support/cli_runner.hpp"

#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace {

using hemicontact::test::slurp;

TEST(House, TheFuzzDictionaryHoldsEverySchemaKey) {
  const std::string doc = slurp(HEMICONTACT_SOURCE_DIR "/docs/scene-format.md");
  const std::string dict = slurp(HEMICONTACT_SOURCE_DIR "/fuzz/scene.dict");
  ASSERT_FALSE(doc.empty());
  ASSERT_FALSE(dict.empty());
  std::set<std::string> tokens;
  std::istringstream lines(dict);
  for (std::string line; std::getline(lines, line);)
    if (line.size() > 2 && line.front() == '"') tokens.insert(line.substr(1, line.size() - 2));
  const std::regex row(R"(\n\| `([^`]+)`)");
  const std::regex sep(R"([.\[\]*]+)");
  int keys = 0;
  for (auto it = std::sregex_iterator(doc.begin(), doc.end(), row); it != std::sregex_iterator(); ++it, ++keys) {
    const std::string key = (*it)[1];
    for (auto p = std::sregex_token_iterator(key.begin(), key.end(), sep, -1); p != std::sregex_token_iterator(); ++p) {
      if (p->str().empty()) continue;
      EXPECT_TRUE(tokens.count(p->str())) << "'" << p->str() << "' of scene key " << key
                                          << " is not in fuzz/scene.dict: run python3 fuzz/make_corpus.py";
    }
  }
  EXPECT_GT(keys, 50);  // the schema's table was read
}

}  // namespace
