// Typed, enum-keyed options with bounds (the table in options.cpp is the one
// place an option is declared).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "unimesh.h"

namespace um {

struct OptionSpec {
    um_option key;
    const char *name;  // as used in "name=value;..." strings
    int32_t type;      // UM_OPTION_TYPE_INT or UM_OPTION_TYPE_REAL
    double min_value, max_value, default_value;
};

// The spec of a key; throws UM_ERR_UNKNOWN_OPTION.
const OptionSpec &option_spec(um_option key);
// The spec of a name; nullptr when unknown.
const OptionSpec *option_spec_by_name(const std::string &name);

class Options {
public:
    Options();
    // Both throw (UM_ERR_UNKNOWN_OPTION, UM_ERR_OPTION_TYPE, UM_ERR_INVALID_ARGUMENT)
    // naming the key and value, and change nothing on failure.
    void set_real(um_option key, double value);
    void set_int(um_option key, int64_t value);
    double real(um_option key) const;
    int64_t integer(um_option key) const;
    // "name=value;..." all-or-nothing.
    void set_from_string(const std::string &assignments);

private:
    std::vector<double> values_;  // by index in the spec table; ints stored exactly
};

}  // namespace um
