// JSON text the command-line tool writes itself (quality --json, the run's
// manifest).
#pragma once

#include <cstdio>
#include <string>

// A string's JSON form between its quotes: quotes, backslashes and control
// characters escaped (a path may hold any of them).
inline std::string json_escaped(const std::string &s) {
    std::string out;
    for (unsigned char c : s) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += static_cast<char>(c);
        } else if (c < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
        } else {
            out += static_cast<char>(c);
        }
    }
    return out;
}
