// docs/scene.md against the reader's schema (scene_schema): every key the
// reader accepts is documented in the reference, and every key a table of
// the reference documents is one the reader accepts.
#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "support/test_support.hpp"
#include "tensormass/scene/scene.hpp"

namespace {

/// The reference from its "## Keys" heading on (the examples above it are
/// not the reference), without its code fences (their three backticks would
/// pair with the spans').
std::string reference_keys_part() {
  const std::string text = test_support::read_file(test_support::source_path("docs/scene.md"));
  const std::size_t keys = text.find("\n## Keys");
  if (keys == std::string::npos) return "";
  std::istringstream lines(text.substr(keys));
  std::string result, line;
  while (std::getline(lines, line))
    if (line.rfind("```", 0) != 0) result += line + "\n";
  return result;
}

/// Every word inside a `...` span.
std::set<std::string> backticked_words(const std::string& text) {
  std::set<std::string> words;
  const std::regex span("`([^`]+)`"), word("[A-Za-z_][A-Za-z0-9_]*");
  for (auto s = std::sregex_iterator(text.begin(), text.end(), span); s != std::sregex_iterator(); ++s) {
    const std::string inside = (*s)[1];
    for (auto w = std::sregex_iterator(inside.begin(), inside.end(), word); w != std::sregex_iterator(); ++w)
      words.insert(w->str());
  }
  return words;
}

/// The first cell of each row of the tables whose header starts "| key |",
/// where it is one backticked key: "| `key` | ...".
std::set<std::string> tabled_keys(const std::string& text) {
  std::set<std::string> keys;
  const std::regex row(R"(^\| `([A-Za-z_][A-Za-z0-9_]*)` \|)");
  std::istringstream lines(text);
  bool in_key_table = false;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("| key |", 0) == 0) in_key_table = true;
    else if (line.rfind("|", 0) != 0) in_key_table = false;
    std::smatch match;
    if (in_key_table && std::regex_search(line, match, row)) keys.insert(match[1]);
  }
  return keys;
}

TEST(SceneReference, DocumentsEveryKeyTheReaderAccepts) {
  const std::string reference = reference_keys_part();
  ASSERT_FALSE(reference.empty()) << "docs/scene.md has no '## Keys' section";
  const std::set<std::string> documented = backticked_words(reference);
  for (const auto& [path, keys] : tensormass::scene_schema())
    for (const std::string& key : keys)
      EXPECT_TRUE(documented.count(key)) << "docs/scene.md does not document " << (path.empty() ? "" : path + ".")
                                         << key;
}

TEST(SceneReference, DocumentsNoKeyTheReaderRefuses) {
  std::set<std::string> accepted;
  for (const auto& [path, keys] : tensormass::scene_schema()) accepted.insert(keys.begin(), keys.end());
  const std::set<std::string> tabled = tabled_keys(reference_keys_part());
  ASSERT_GT(tabled.size(), 20u) << "the reference's key tables were not found";
  for (const std::string& key : tabled)
    EXPECT_TRUE(accepted.count(key)) << "docs/scene.md tables `" << key << "`, which no scene map accepts";
}

}  // namespace
