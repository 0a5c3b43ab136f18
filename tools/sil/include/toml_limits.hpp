// toml_limits.hpp - the limits a scenario's TOML text is held to before it is parsed.
//
// The TOML parser (toml++) recurses once per nesting level and builds one table per key segment:
// a file of deep dotted keys or nested headers overflows the stack before any error can be given.
// check_toml_limits scans the text once, without recursion or allocation proportional to its
// depth, and refuses what no scenario needs: a text above kMaxScenarioBytes, a key of more than
// kMaxKeySegments dotted parts (scenario keys have two: [section] key), a key part longer than
// kMaxKeyBytes, or arrays and inline tables nested more than kMaxValueDepth deep.
#ifndef DTC_SIL_TOML_LIMITS_HPP
#define DTC_SIL_TOML_LIMITS_HPP

#include <cstddef>
#include <string>

namespace sil {

inline constexpr std::size_t kMaxScenarioBytes = 1u << 20; // a scenario is a few KB
inline constexpr std::size_t kMaxKeySegments = 8;
inline constexpr std::size_t kMaxKeyBytes = 128;
inline constexpr std::size_t kMaxValueDepth = 8;
/// A value or key is quoted in messages up to this many bytes, then cut ("... (N bytes)").
inline constexpr std::size_t kMaxEchoBytes = 80;

/// Empty when text is within the limits; else "source:line:col: why" for the first excess.
std::string check_toml_limits(const std::string& text, const std::string& source_name);

/// s itself when it is at most kMaxEchoBytes long; else its start, "...", and its length.
std::string echo(const std::string& s);

} // namespace sil

#endif // DTC_SIL_TOML_LIMITS_HPP
