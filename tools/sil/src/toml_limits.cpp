// toml_limits.cpp - see toml_limits.hpp.
#include "toml_limits.hpp"

#include <vector>

namespace sil {

std::string echo(const std::string& s)
{
    if (s.size() <= kMaxEchoBytes) {
        return s;
    }
    return s.substr(0, kMaxEchoBytes) + "... (" + std::to_string(s.size()) + " bytes)";
}

std::string check_toml_limits(const std::string& text, const std::string& source_name)
{
    if (text.size() > kMaxScenarioBytes) {
        return source_name + ": " + std::to_string(text.size()) + " bytes, above the " +
               std::to_string(kMaxScenarioBytes) + " bytes a scenario file may hold (a scenario is a few KB)";
    }
    std::size_t line = 1, col = 1;
    auto at = [&](const std::string& why) {
        return source_name + ":" + std::to_string(line) + ":" + std::to_string(col) + ": " + why;
    };
    // Open arrays ('[') and inline tables ('{'); a header's brackets are not values.
    std::vector<char> open;
    open.reserve(kMaxValueDepth + 1);
    bool line_start = true;  // only whitespace so far on this line
    bool in_key = false;     // reading a key (before its '=') or a [header]
    bool in_header = false;
    std::size_t segments = 0, seg_bytes = 0;
    const std::size_t n = text.size();
    auto start_key = [&] {
        in_key = true;
        segments = 1;
        seg_bytes = 0;
    };
    for (std::size_t i = 0; i < n; ++i) {
        const char c = text[i];
        if (c == '\n') {
            ++line;
            col = 1;
            line_start = true;
            if (in_key && !in_header && open.empty()) {
                in_key = false; // a key without '=': the parser reports it
            }
            continue;
        }
        const bool blank = c == ' ' || c == '\t' || c == '\r';
        if (line_start && !blank && open.empty()) {
            line_start = false;
            if (c == '[') {
                in_header = true;
                start_key();
                if (i + 1 < n && text[i + 1] == '[') {
                    ++i;
                    ++col;
                }
                ++col;
                continue;
            }
            if (c != '#') {
                start_key();
            }
        }
        if (c == '#') { // comment to the end of the line
            while (i + 1 < n && text[i + 1] != '\n') {
                ++i;
            }
            continue;
        }
        if (c == '"' || c == '\'') {
            const bool multi = i + 2 < n && text[i + 1] == c && text[i + 2] == c;
            const std::size_t start = i;
            i += multi ? 3 : 1;
            while (i < n) {
                if (c == '"' && text[i] == '\\') {
                    i += 2;
                    continue;
                }
                if (text[i] == '\n') {
                    if (!multi) {
                        break; // unterminated: the parser reports it
                    }
                    ++line;
                    col = 0;
                }
                if (text[i] == c && (!multi || (i + 2 < n && text[i + 1] == c && text[i + 2] == c))) {
                    i += multi ? 2 : 0;
                    break;
                }
                ++i;
                ++col;
            }
            if (in_key) {
                seg_bytes += i - start;
                if (seg_bytes > kMaxKeyBytes + 2) {
                    return at("a key longer than " + std::to_string(kMaxKeyBytes) +
                              " bytes (scenario keys are short names: dtc-sil keys lists them)");
                }
            }
            ++col;
            continue;
        }
        if (in_key && c == '}' && !in_header) {
            in_key = false; // "{}": an empty inline table; closed below
        } else if (in_key) {
            if (c == '.') {
                if (++segments > kMaxKeySegments) {
                    return at("a key of more than " + std::to_string(kMaxKeySegments) +
                              " dotted parts (scenario keys have two: [section] key)");
                }
                seg_bytes = 0;
            } else if (c == '=' && !in_header) {
                in_key = false;
            } else if (c == ']' && in_header) {
                in_key = false;
                in_header = false;
            } else if (!blank) {
                if (++seg_bytes > kMaxKeyBytes) {
                    return at("a key longer than " + std::to_string(kMaxKeyBytes) +
                              " bytes (scenario keys are short names: dtc-sil keys lists them)");
                }
            }
            ++col;
            continue;
        }
        if (c == '[' || c == '{') {
            if (open.size() >= kMaxValueDepth) {
                return at("arrays or inline tables nested more than " + std::to_string(kMaxValueDepth) +
                          " deep (a scenario value needs at most 2)");
            }
            open.push_back(c);
            if (c == '{') {
                start_key();
            }
        } else if ((c == ']' || c == '}') && !open.empty()) {
            open.pop_back();
        } else if (c == ',' && !open.empty() && open.back() == '{') {
            start_key();
        }
        ++col;
    }
    return "";
}

} // namespace sil
