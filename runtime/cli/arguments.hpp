/// \file arguments.hpp
/// Small helpers shared by the subcommands' option parsers.
#ifndef TENSORMASS_CLI_ARGUMENTS_HPP
#define TENSORMASS_CLI_ARGUMENTS_HPP

#include <string>
#include <string_view>
#include <vector>

namespace tensormass::cli {

/// "a,b,c" -> {"a", "b", "c"} (empty fields kept).
inline std::vector<std::string> split_commas(std::string_view text) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t comma; (comma = text.find(',', start)) != std::string_view::npos; start = comma + 1)
    parts.emplace_back(text.substr(start, comma - start));
  parts.emplace_back(text.substr(start));
  return parts;
}

}  // namespace tensormass::cli

#endif
