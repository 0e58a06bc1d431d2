#include "io/netcdf_header.hpp"

#include <netcdf.h>

#include <cstdint>
#include <algorithm>
#include <fstream>
#include <vector>

#include "core/text.hpp"

namespace um::io {

namespace {

// Reads big-endian fields of a classic header, remembering the first problem.
class HeaderReader {
public:
    HeaderReader(std::vector<unsigned char> bytes, int version)
        : b_(std::move(bytes)), wide_(version == 5 ? 8 : 4), offset_(version == 1 ? 4 : 8) {}

    bool failed() const { return !problem_.empty(); }
    // Whether the first problem was running out of bytes (or of room for a count).
    bool short_of_bytes() const { return short_; }
    const std::string &problem() const { return problem_; }

    uint64_t number(int width) {
        if (failed()) return 0;
        if (at_ + uint64_t(width) > b_.size()) return fail_short("the header ends early"), 0;
        uint64_t v = 0;
        for (int i = 0; i < width; ++i) v = v << 8 | b_[at_ + i];
        at_ += uint64_t(width);
        return v;
    }
    uint64_t count() { return number(wide_); }
    // A count of items of at least min_bytes each that the rest must hold.
    uint64_t items(uint64_t min_bytes, const char *what) {
        const uint64_t n = count();
        if (!failed() && n > (b_.size() - at_) / min_bytes) fail_short(concat(n, " ", what, " cannot fit in the file"));
        return failed() ? 0 : n;
    }
    std::string name() {
        const uint64_t n = count();
        if (failed()) return "";
        if (n > NC_MAX_NAME) return fail_at(concat("a name of ", n, " bytes (at most ", NC_MAX_NAME, ")")), "";
        const uint64_t at = at_;
        skip(pad4(n));
        return failed() ? "" : std::string(b_.begin() + at, b_.begin() + at + n);
    }
    void skip(uint64_t n) {
        if (failed()) return;
        if (n > b_.size() - at_) return fail_short("the header ends early");
        at_ += n;
    }
    // An absent list is two zero words; a present one has its tag.
    uint64_t list(uint32_t tag, uint64_t min_item, const char *what) {
        const uint64_t t = number(4);
        const uint64_t n = items(min_item, what);
        if (!failed() && t != tag && !(t == 0 && n == 0)) fail_at(concat("a list tag ", t, " where ", tag, " belongs"));
        return n;
    }
    // Into *found when given (the global attributes).
    void attributes(std::vector<ClassicLayout::Attribute> *found = nullptr) {
        const uint64_t n = list(NC_ATTRIBUTE_TAG, 12, "attributes");
        for (uint64_t a = 0; a < n && !failed(); ++a) {
            std::string attribute = name();
            const uint64_t type = number(4);
            const int size = type_size(type);
            if (size == 0 && !failed()) return fail_at(concat("an attribute of type ", type));
            const uint64_t values = items(uint64_t(size), "attribute values");
            if (found && !failed()) found->push_back({std::move(attribute), at_, values * uint64_t(size)});
            skip(pad4(values * uint64_t(size)));
        }
    }
    void header(ClassicLayout &layout) {
        skip(4);  // magic
        // (All ones: a file being streamed, its records not counted yet; none
        // are counted against its length then.)
        uint64_t records = number(wide_);
        if (records == (wide_ == 8 ? ~uint64_t(0) : uint64_t(0xFFFFFFFFu))) records = 0;
        const uint64_t ndims = list(NC_DIMENSION_TAG, 8, "dimensions");
        std::vector<uint64_t> length;  // the record dimension's (0): the records
        for (uint64_t d = 0; d < ndims && !failed(); ++d) {
            name();
            const uint64_t n = count();
            length.push_back(n == 0 ? records : n);
        }
        attributes(&layout.global_attributes);
        const uint64_t nvars = list(NC_VARIABLE_TAG, 16, "variables");
        for (uint64_t v = 0; v < nvars && !failed(); ++v) {
            std::string variable = name();
            const uint64_t rank = items(uint64_t(wide_), "dimension ids");
            uint64_t values = 1;
            for (uint64_t k = 0; k < rank && !failed(); ++k) {
                const uint64_t d = count();
                if (d >= ndims && !failed()) fail_at("a variable on a dimension that does not exist");
                if (!failed()) values = saturated_product(values, length[d]);
            }
            attributes();
            const int size = type_size(number(4));
            if (size == 0 && !failed()) fail_at("a variable of an unknown type");
            count();                                 // vsize
            const uint64_t begin = number(offset_);
            if (failed()) break;
            layout.variables.push_back({std::move(variable), begin});
            layout.data_bytes = std::min(kHuge, layout.data_bytes + saturated_product(values, uint64_t(size)));
        }
        layout.header_bytes = at_;
    }

private:
    // Sizes past this are as good as infinite: a hostile header's dimensions
    // may multiply past 64 bits.
    static constexpr uint64_t kHuge = uint64_t(1) << 62;
    static uint64_t saturated_product(uint64_t a, uint64_t b) {
        uint64_t p;
        return __builtin_mul_overflow(a, b, &p) || p > kHuge ? kHuge : p;
    }
    static constexpr uint32_t NC_DIMENSION_TAG = 0x0A, NC_VARIABLE_TAG = 0x0B, NC_ATTRIBUTE_TAG = 0x0C;
    static uint64_t pad4(uint64_t n) { return (n + 3) / 4 * 4; }
    static int type_size(uint64_t type) {
        switch (type) {
            case NC_BYTE: case NC_CHAR: case NC_UBYTE: return 1;
            case NC_SHORT: case NC_USHORT: return 2;
            case NC_INT: case NC_FLOAT: case NC_UINT: return 4;
            case NC_DOUBLE: case NC_INT64: case NC_UINT64: return 8;
            default: return 0;
        }
    }
    void fail_at(const std::string &what) {
        if (problem_.empty()) problem_ = concat(what, " (header byte ", at_, ")");
    }
    // A problem that more of the file might not have had.
    void fail_short(const std::string &what) {
        if (!failed()) short_ = true;
        fail_at(what);
    }

    std::vector<unsigned char> b_;
    int wide_, offset_;
    uint64_t at_ = 0;
    std::string problem_;
    bool short_ = false;
};

}  // namespace

std::string read_classic_layout(const std::string &path, ClassicLayout &layout) {
    layout = ClassicLayout{};
    std::ifstream in(path, std::ios::binary);
    if (!in) return "";  // netCDF's own open reports it
    char magic[4] = {0, 0, 0, 0};
    in.read(magic, 4);
    if (!in || magic[0] != 'C' || magic[1] != 'D' || magic[2] != 'F' ||
        (magic[3] != 1 && magic[3] != 2 && magic[3] != 5))
        return "";
    in.seekg(0, std::ios::end);
    const uint64_t file_bytes = static_cast<uint64_t>(in.tellg());
    // The header is read from a prefix of the file, doubled while that is
    // too short to hold it: a count that a prefix "cannot fit" may fit the
    // whole file, and what a prefix holds the whole file holds, so the
    // answer is the whole file's without reading gigabytes of values. Other
    // problems are the same in any prefix.
    for (uint64_t prefix = uint64_t(1) << 20;; prefix *= 2) {
        const uint64_t n = std::min(prefix, file_bytes);
        std::vector<unsigned char> bytes(n);
        in.clear();
        in.seekg(0);
        in.read(reinterpret_cast<char *>(bytes.data()), static_cast<std::streamsize>(n));
        if (!in) return concat("the first ", n, " bytes cannot be read");
        HeaderReader reader(std::move(bytes), magic[3]);
        layout = ClassicLayout{};
        reader.header(layout);
        layout.classic = true;
        if (!reader.short_of_bytes() || n == file_bytes) return reader.problem();
    }
}

std::string classic_header_problem(const std::string &path) {
    ClassicLayout layout;
    return read_classic_layout(path, layout);
}

}  // namespace um::io
