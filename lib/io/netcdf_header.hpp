// A check of a netCDF classic-format header (CDF-1, CDF-2, CDF-5) before
// netCDF-C opens the file. netCDF-C trusts the counts and name lengths a
// header declares: a corrupt file can make it allocate what the header
// claims (15 GB seen) or copy an over-long name past the NC_MAX_NAME buffer
// its API promises (both found by fuzzing the spacing-file reader). This
// walks the header as the format specification lays it out and refuses any
// count that the file's remaining bytes cannot hold and any name longer
// than NC_MAX_NAME.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace um::io {

// Where a classic file's header puts things: the byte offset of each
// variable's values (its "begin"), of each global attribute's values, the
// header's length, and how many bytes of values it declares (every
// variable's, the record variables' for the records it counts; at most
// 2^62).
struct ClassicLayout {
    struct Variable {
        std::string name;
        uint64_t begin;
    };
    struct Attribute {
        std::string name;
        uint64_t offset, bytes;
    };
    bool classic = false;  // false: not a classic-format file
    std::vector<Variable> variables;
    std::vector<Attribute> global_attributes;
    uint64_t header_bytes = 0, data_bytes = 0;
};

// classic_header_problem's check, keeping what the header says in layout
// (as far as it could be read when there is a problem).
std::string read_classic_layout(const std::string &path, ClassicLayout &layout);

// "" when path is not a classic-format file (HDF5-based netCDF-4 is left to
// netCDF) or its header is sound; otherwise what is wrong and where.
std::string classic_header_problem(const std::string &path);

}  // namespace um::io
