// Locale-independent text building for messages and files: the host program
// may have changed the C or C++ locale, and our messages and outputs must not
// change with it.
#pragma once

#include <charconv>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>

namespace um {

// Shortest text that reads back to the same double ("nan", "inf", "-inf" too).
inline std::string to_text(double v) {
    char buf[64];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

// v with at most `decimals` decimals, trailing zeros dropped ("-0" as "0"):
// a computed place in a message, whose last bits are rounding.
inline std::string rounded_text(double v, int decimals) {
    char buf[400];
    auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
    if (r.ec != std::errc()) return to_text(v);
    std::string s(buf, r.ptr);
    if (s.find('.') != std::string::npos) {
        while (s.back() == '0') s.pop_back();
        if (s.back() == '.') s.pop_back();
    }
    return s == "-0" ? "0" : s;
}

template <class T>
std::string to_text(T v) {
    if constexpr (std::is_same_v<T, bool>) {
        return v ? "true" : "false";
    } else if constexpr (std::is_integral_v<T>) {
        char buf[32];
        auto r = std::to_chars(buf, buf + sizeof buf, v);
        return std::string(buf, r.ptr);
    } else if constexpr (std::is_floating_point_v<T>) {
        return to_text(static_cast<double>(v));
    } else {
        return std::string(std::string_view(v));
    }
}

inline void append_all(std::string &) {}
template <class First, class... Rest>
void append_all(std::string &out, const First &first, const Rest &...rest) {
    out += to_text(first);
    append_all(out, rest...);
}

template <class... Parts>
std::string concat(const Parts &...parts) {
    std::string out;
    append_all(out, parts...);
    return out;
}

}  // namespace um
