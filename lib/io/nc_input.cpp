#include "io/nc_input.hpp"

#include <cstring>
#include <algorithm>
#include <filesystem>
#include <limits>
#include <system_error>

#include <netcdf.h>

#include "core/error.hpp"
#include "io/error_text.hpp"
#include "io/input_file.hpp"
#include "io/netcdf_header.hpp"

namespace um::io {

namespace {

// Classic-format (CDF-1/2/5) header size, from the structure the format
// specification gives; CDF-5 widens counts and lengths to 8 bytes.
class ClassicHeaderSize {
public:
    ClassicHeaderSize(int ncid, int format) : id_(ncid), wide_(format == NC_FORMAT_CDF5 ? 8 : 4) {}
    int64_t total() const {
        int ndims = 0, nvars = 0, ngatts = 0;
        if (nc_inq(id_, &ndims, &nvars, &ngatts, nullptr) != NC_NOERR) return 0;
        int64_t size = 4 + wide_ + list(ndims, [&](int d) { return dimension(d); }) +
                       attributes(NC_GLOBAL, ngatts);
        return size + list(nvars, [&](int v) { return variable(v); });
    }

private:
    static int64_t pad4(int64_t n) { return (n + 3) / 4 * 4; }
    template <class Item>
    int64_t list(int n, Item item) const {  // tag, count, items
        int64_t size = 4 + wide_;
        for (int k = 0; k < n; ++k) size += item(k);
        return size;
    }
    int64_t name(const char *text) const { return wide_ + pad4(int64_t(std::strlen(text))); }
    int64_t dimension(int d) const {
        char text[NC_MAX_NAME + 1] = "";
        nc_inq_dimname(id_, d, text);
        return name(text) + wide_;
    }
    int64_t attributes(int var, int n) const {
        return list(n, [&](int a) {
            char text[NC_MAX_NAME + 1] = "";
            nc_type type = NC_NAT;
            size_t count = 0, type_size = 0;
            nc_inq_attname(id_, var, a, text);
            nc_inq_att(id_, var, text, &type, &count);
            nc_inq_type(id_, type, nullptr, &type_size);
            return name(text) + 4 + wide_ + pad4(int64_t(count * type_size));
        });
    }
    int64_t variable(int v) const {
        char text[NC_MAX_NAME + 1] = "";
        int ndims = 0, natts = 0;
        nc_inq_var(id_, v, text, nullptr, &ndims, nullptr, &natts);
        return name(text) + wide_ + wide_ * ndims + attributes(v, natts) + 4 + wide_ +
               (wide_ == 8 ? 8 : offset_size());
    }
    int64_t offset_size() const {  // "begin" is 8 bytes from CDF-2 on
        int format = 0;
        nc_inq_format(id_, &format);
        return format == NC_FORMAT_CLASSIC ? 4 : 8;
    }

    int id_;
    int64_t wide_;
};

}  // namespace

NcInput::NcInput(const std::string &path, const char *what) {
    require_regular_input(path, what);
    // netCDF-C trusts a classic header's counts and name lengths.
    const std::string problem = classic_header_problem(path);
    if (!problem.empty()) fail(UM_ERR_FILE_FORMAT, what, " '", path, "': its netCDF header is malformed: ", problem);
    int status = nc_open(path.c_str(), NC_NOWRITE, &id_);
    // netCDF returns errno values (> 0) for system errors and its own
    // negative codes when the bytes are not a readable netCDF file.
    if (status > 0) fail(UM_ERR_IO, "cannot open ", what, " '", path, "': ", netcdf_status_text(status));
    if (status != NC_NOERR) {
        id_ = -1;
        fail(UM_ERR_FILE_FORMAT, what, " '", path, "': not a readable netCDF file (", netcdf_status_text(status),
             "): not netCDF, damaged or truncated");
    }
    try {
        check_classic_length(path, what);
    } catch (...) {
        nc_close(id_);
        throw;
    }
}

NcInput::~NcInput() {
    if (id_ >= 0) nc_close(id_);
}

// netCDF-C reads the missing tail of a truncated classic file as zeros without
// an error, so the length is checked against its header plus its data.
void NcInput::check_classic_length(const std::string &path, const char *what) const {
    int format = 0;
    if (nc_inq_format(id_, &format) != NC_NOERR ||
        (format != NC_FORMAT_CLASSIC && format != NC_FORMAT_64BIT_OFFSET && format != NC_FORMAT_CDF5))
        return;
    int nvars = 0;
    nc_inq_nvars(id_, &nvars);
    int64_t needed = ClassicHeaderSize(id_, format).total();
    for (int v = 0; v < nvars; ++v) {
        nc_type type = NC_NAT;
        int ndims = 0, dims[NC_MAX_VAR_DIMS];
        size_t type_size = 0, length = 0;
        nc_inq_var(id_, v, nullptr, &type, &ndims, dims, nullptr);
        nc_inq_type(id_, type, nullptr, &type_size);
        // Saturating: a hostile header's dimensions may multiply past int64.
        constexpr int64_t kHuge = std::numeric_limits<int64_t>::max() / 2;
        int64_t bytes = int64_t(type_size);
        for (int k = 0; k < ndims; ++k) {
            nc_inq_dimlen(id_, dims[k], &length);
            if (__builtin_mul_overflow(bytes, int64_t(length), &bytes) || bytes > kHuge) bytes = kHuge;
        }
        needed = std::min(kHuge, needed + bytes);
    }
    std::error_code error;
    const auto actual = std::filesystem::file_size(path, error);
    if (!error && int64_t(actual) < needed)
        fail(UM_ERR_FILE_FORMAT, what, " '", path, "': the file is truncated: it has ", int64_t(actual),
             " bytes, its header and data need at least ", needed);
}

}  // namespace um::io
