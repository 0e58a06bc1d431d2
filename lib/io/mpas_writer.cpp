#include "io/mpas_writer.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <functional>
#include <memory>
#include <mutex>
#include <filesystem>
#include <system_error>
#include <type_traits>
#include <vector>

#include <netcdf.h>

#include "core/error.hpp"
#include "core/uninit_vector.hpp"
#include "dual/mpas_fields.hpp"
#include "dual/mpas_source.hpp"
#include "io/error_text.hpp"
#include "io/nc_output.hpp"
#include "io/netcdf_header.hpp"
#include "io/direct_regions.hpp"
#include "io/netcdf_lock.hpp"

namespace um::io {

namespace {

using dual::MpasMesh;

using dual::MpasDim;
using dual::MpasField;
using dual::MpasKind;

// ----------------------------------------------------------------- file_id

struct Hash {
    uint64_t h = 0x6a09e667f3bcc908ull;
    void word(uint64_t w) {
        h ^= w + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
        h *= 0xff51afd7ed558ccdull;
        h ^= h >> 33;
    }
};

// n bytes into a hash: their count, then 8-byte words, then the last
// partial word padded with zeros; fed in pieces of any size (blocks of
// rows), with the same result for any way of cutting them. Word k goes to
// lane k % 4 and the lanes are folded in at the end: four independent
// chains of multiplications run side by side, about four times as fast as
// one over a file of gigabytes (the writer's thread hashes every value).
class ByteStream {
public:
    ByteStream(Hash start, uint64_t total_bytes) : hash_(start) {
        hash_.word(total_bytes);
        for (int k = 0; k < kLanes; ++k) lanes_[k].word(static_cast<uint64_t>(k));
    }
    void feed(const void *data, size_t n) {
        const unsigned char *p = static_cast<const unsigned char *>(data);
        while (n > 0 && (filled_ != 0 || lane_ != 0)) take_byte(p, n);
        for (; n >= 8 * kLanes; p += 8 * kLanes, n -= 8 * kLanes) {  // most of a file's bytes
            uint64_t w[kLanes];
            std::memcpy(w, p, sizeof w);
            for (int k = 0; k < kLanes; ++k) lanes_[k].word(w[k]);
        }
        while (n > 0) take_byte(p, n);
    }
    Hash finish() {
        uint64_t tail = 0;
        std::memcpy(&tail, pending_, filled_);
        lanes_[lane_].word(tail);
        for (const Hash &lane : lanes_) hash_.word(lane.h);
        return hash_;
    }

private:
    static constexpr int kLanes = 4;
    void take_byte(const unsigned char *&p, size_t &n) {
        pending_[filled_++] = *p++, --n;
        if (filled_ < 8) return;
        uint64_t w;
        std::memcpy(&w, pending_, 8);
        lanes_[lane_].word(w);
        lane_ = (lane_ + 1) % kLanes, filled_ = 0;
    }
    Hash hash_, lanes_[kLanes];
    unsigned char pending_[8] = {};
    size_t filled_ = 0;
    int lane_ = 0;
};

Hash with_bytes(Hash hash, const void *data, size_t n) {
    ByteStream stream(hash, n);
    stream.feed(data, n);
    return stream.finish();
}

// file_id: the radius, each variable's name and the hash of its values (its
// row count for the indexTo*ID variables), then a final avalanche and 10
// base-36 digits (36^10 < 2^52).
std::string file_id_of(double radius, const std::vector<MpasField> &fields, const std::vector<uint64_t> &value_hashes) {
    Hash hash = with_bytes(Hash{}, &radius, sizeof radius);
    for (size_t i = 0; i < fields.size(); ++i) {
        hash = with_bytes(hash, fields[i].name, std::strlen(fields[i].name));
        hash.word(value_hashes[i]);
    }
    uint64_t h = hash.h;
    h ^= h >> 31, h *= 0x94d049bb133111ebull, h ^= h >> 29;
    const char digits[] = "0123456789abcdefghijklmnopqrstuvwxyz";
    std::string id(10, '0');
    for (char &c : id) c = digits[h % 36], h /= 36;
    return id;
}

// ----------------------------------------------------------------- netCDF

size_t dim_length(const MpasMesh &m, MpasDim d) {
    return static_cast<size_t>(dual::mpas_dim_length(m, d));
}

size_t row_width(const MpasMesh &m, const MpasField &f) { return static_cast<size_t>(f.columns(m)); }

uint64_t value_bytes(const MpasMesh &m, const MpasField &f) {
    uint64_t bytes = f.kind == MpasKind::real ? 8 : 4;
    for (MpasDim d : f.dims) bytes *= dim_length(m, d);
    return bytes;
}

// 64-bit offset files hold fixed-size variables of up to 2^32 - 4 bytes;
// larger meshes (weightsOnEdge passes it at about 8 M cells) need CDF-5.
int format_for(const MpasMesh &m, const std::vector<MpasField> &fields, const MpasWriteOptions &options) {
    if (options.format == MpasFileFormat::netcdf4) return NC_NETCDF4;
    for (const MpasField &f : fields)
        if (value_bytes(m, f) > options.variable_limit) return NC_64BIT_DATA;
    return NC_64BIT_OFFSET;
}

// The file_id attribute is written last, when the values are known: a
// placeholder of the same length first, so that the header keeps its size
// and nothing moves when it is replaced.
constexpr const char *kFileIdPlaceholder = "0000000000";

// What a mesh made on an ellipsoid holds, for readers who know MPAS assumes
// a sphere (unimesh.h, "Surfaces").
void write_ellipsoid_attributes(const NcOutput &nc, const MpasMesh &m) {
    nc.put_text(NC_GLOBAL, "surface", "ellipsoid");
    nc.check(nc_put_att_double(nc.id(), NC_GLOBAL, "ellipsoid_semi_major_axis", NC_DOUBLE, 1, &m.ellipsoid_a_m),
             "writing attribute ellipsoid_semi_major_axis");
    nc.check(nc_put_att_double(nc.id(), NC_GLOBAL, "ellipsoid_flattening", NC_DOUBLE, 1, &m.ellipsoid_f),
             "writing attribute ellipsoid_flattening");
    nc.put_text(NC_GLOBAL, "surface_note",
                "made on the ellipsoid (ellipsoid_semi_major_axis, ellipsoid_flattening); written as MPAS "
                "assumes a sphere: cells, edges and vertices at the geodetic latitude and longitude of their "
                "ellipsoid points, on the sphere of radius sphere_radius (the ellipsoid's authalic radius, so "
                "the cell areas add up to the ellipsoid's area); every length, area and weight is of that sphere");
}

void define(const NcOutput &nc, const MpasMesh &m, const std::vector<MpasField> &fields,
            std::vector<int> &var_ids) {
    int dim_ids[dual::kMpasDimCount];
    for (int d = 0; d < dual::kMpasDimCount; ++d) {
        const MpasDim dim = static_cast<MpasDim>(d);
        const size_t length = dim == MpasDim::Time ? NC_UNLIMITED : dim_length(m, dim);
        nc.check(nc_def_dim(nc.id(), dual::mpas_dim_name(dim), length, &dim_ids[d]),
                 "defining dimension ", dual::mpas_dim_name(dim));
    }
    for (const MpasField &f : fields) {
        int dims[2], var = -1;
        for (size_t k = 0; k < f.dims.size(); ++k) dims[k] = dim_ids[static_cast<int>(f.dims[k])];
        nc_type type = f.kind == MpasKind::real ? NC_DOUBLE : NC_INT;
        nc.check(nc_def_var(nc.id(), f.name, type, static_cast<int>(f.dims.size()), dims, &var),
                 "defining variable ", f.name);
        nc.put_text(var, "long_name", f.long_name);
        if (f.units) nc.put_text(var, "units", f.units);
        if (f.n_flags > 0) {
            nc.check(nc_put_att_int(nc.id(), var, "flag_values", NC_INT, f.n_flags, f.flag_values),
                     "writing attribute flag_values of ", f.name);
            nc.put_text(var, "flag_meanings", f.flag_meanings);
        }
        var_ids.push_back(var);
    }
    nc.put_text(NC_GLOBAL, "on_a_sphere", "YES");
    nc.check(nc_put_att_double(nc.id(), NC_GLOBAL, "sphere_radius", NC_DOUBLE, 1, &m.radius_m),
             "writing attribute sphere_radius");
    if (m.ellipsoid_f > 0) write_ellipsoid_attributes(nc, m);
    nc.put_text(NC_GLOBAL, "is_periodic", "NO");
    nc.put_text(NC_GLOBAL, "mesh_spec", "1.0");
    nc.put_text(NC_GLOBAL, "Conventions", "MPAS");
    nc.put_text(NC_GLOBAL, "source", "unimesh " UM_VERSION_STRING);
    nc.put_text(NC_GLOBAL, "file_id", kFileIdPlaceholder);
}

// Where a block's values go. A classic file's are written straight to the
// byte offsets its header gives each variable, big-endian as the format lays
// them out: netCDF's own classic I/O reads each region of the file back
// before writing into it (zero-filled pages of a file not yet written, a
// quarter of the MPAS stage's processor time at 10 km). A netCDF-4 file's
// go through netCDF, under the netCDF lock.
class ValueWriter {
public:
    // begins: each variable's offset in a classic file (unused through
    // netCDF); direct: its regions when written around the page cache.
    ValueWriter(const NcOutput &nc, const std::vector<int> &var_ids, bool through_netcdf,
                std::vector<uint64_t> begins, DirectRegions *direct)
        : nc_(nc), var_ids_(var_ids), through_netcdf_(through_netcdf), begins_(std::move(begins)), direct_(direct) {}
    bool through_netcdf() const { return through_netcdf_; }

    template <class T>
    void put(size_t field, const char *name, size_t first_row, size_t rows, size_t width, const T *values) {
        const size_t n = rows * width;
        if (through_netcdf()) {
            size_t start[2] = {first_row, 0}, count[2] = {rows, width};
            if constexpr (std::is_same_v<T, double>)
                nc_.check(nc_put_vara_double(nc_.id(), var_ids_[field], start, count, values), "writing variable ", name);
            else
                nc_.check(nc_put_vara_int(nc_.id(), var_ids_[field], start, count, values), "writing variable ", name);
            return;
        }
        bytes_.resize(n * sizeof(T));
        for (size_t i = 0; i < n; ++i) {
            if constexpr (sizeof(T) == 8) {
                uint64_t w;
                std::memcpy(&w, &values[i], 8);
                w = __builtin_bswap64(w);
                std::memcpy(&bytes_[8 * i], &w, 8);
            } else {
                uint32_t w;
                std::memcpy(&w, &values[i], 4);
                w = __builtin_bswap32(w);
                std::memcpy(&bytes_[4 * i], &w, 4);
            }
        }
        const uint64_t offset = begins_[field] + first_row * width * sizeof(T);
        if (direct_) direct_->append(field, offset, bytes_.data(), bytes_.size());
        else nc_.file().write_at(offset, bytes_.data(), bytes_.size());
    }

private:
    const NcOutput &nc_;
    const std::vector<int> &var_ids_;
    bool through_netcdf_;
    std::vector<uint64_t> begins_;
    DirectRegions *direct_;
    UninitVector<unsigned char> bytes_;  // every byte written before it is read
};

// Rows [first, first + count) of f, whose arrays (in block) start at row
// array_first; the values go into the file and into the variable's hash.
struct RowRange {
    int64_t first, count, array_first;
};

void put_rows(ValueWriter &out, size_t field, const MpasMesh &block, const MpasField &f, RowRange r,
              ByteStream &hash, std::vector<int32_t> &buffer) {
    const size_t width = row_width(block, f), values = static_cast<size_t>(r.count) * width;
    const size_t offset = static_cast<size_t>(r.first - r.array_first) * width;
    const size_t have = f.reals ? f.reals->size() : f.ints ? f.ints->size() : offset + values;
    if (have < offset + values)
        fail(UM_ERR_INTERNAL, "MPAS mesh: variable ", f.name, " has ", have, " values, rows up to ",
             r.first + r.count, " asked for");
    const size_t first = static_cast<size_t>(r.first), rows = static_cast<size_t>(r.count);
    if (f.kind == MpasKind::real) {
        out.put(field, f.name, first, rows, width, f.reals->data() + offset);
        hash.feed(f.reals->data() + offset, values * sizeof(double));
    } else if (f.kind == MpasKind::integer) {
        out.put(field, f.name, first, rows, width, f.ints->data() + offset);
        hash.feed(f.ints->data() + offset, values * sizeof(int32_t));
    } else {
        buffer.resize(values);
        for (size_t i = 0; i < values; ++i)
            buffer[i] = f.kind == MpasKind::id ? static_cast<int32_t>(r.first + i + 1)
                                               : (*f.ints)[offset + i] + 1;  // kNone -> 0
        out.put(field, f.name, first, rows, width, buffer.data());
        if (f.ints) hash.feed(f.ints->data() + offset, values * sizeof(int32_t));
    }
}

// The block of a mesh that holds rows [first, first + count) along `kind`,
// made in buffer 0 or 1 (two blocks live at once: one written while the
// next is made); *array_first: the row at which its arrays of that kind
// start.
struct Rows {
    MpasDim kind;
    int64_t first, count;
};
using BlockOf = std::function<const MpasMesh &(int buffer, Rows rows, int64_t *array_first)>;

std::vector<ByteStream> value_hashes_for(const MpasMesh &m, const std::vector<MpasField> &fields) {
    std::vector<ByteStream> hashes;
    for (const MpasField &f : fields) hashes.emplace_back(Hash{}, value_bytes(m, f));  // a variable's values, block by block
    return hashes;
}

std::vector<uint64_t> finish(std::vector<ByteStream> &hashes, const MpasMesh &m, const std::vector<MpasField> &fields) {
    std::vector<uint64_t> out;
    for (size_t i = 0; i < fields.size(); ++i)
        out.push_back(fields[i].kind == MpasKind::id ? dim_length(m, fields[i].dims[0]) : hashes[i].finish().h);
    return out;
}

// Every block of rows, kind by kind.
std::vector<Rows> blocks_of(const MpasMesh &m, int64_t block_rows) {
    std::vector<Rows> blocks;
    for (MpasDim kind : {MpasDim::nCells, MpasDim::nEdges, MpasDim::nVertices}) {
        const int64_t rows = dual::mpas_dim_length(m, kind);
        for (int64_t first = 0; first < rows; first += block_rows)
            blocks.push_back({kind, first, std::min(block_rows, rows - first)});
    }
    return blocks;
}

// A block's variables into the file.
struct FileState {
    ValueWriter &out;
    const std::vector<MpasField> &fields;
    std::vector<ByteStream> &hashes;
    std::vector<int32_t> buffer;
};

void put_block(FileState &file, const MpasMesh &block, Rows rows, int64_t array_first) {
    const std::vector<MpasField> block_fields = dual::mpas_fields(block);
    if (block_fields.size() != file.fields.size())
        fail(UM_ERR_INTERNAL, "MPAS mesh: a block has ", block_fields.size(), " variables, not ", file.fields.size());
    for (size_t i = 0; i < file.fields.size(); ++i)
        if (file.fields[i].dims[0] == rows.kind)
            put_rows(file.out, i, block, block_fields[i], {rows.first, rows.count, array_first}, file.hashes[i],
                     file.buffer);
}

// The offsets of the variables' values and of file_id's in the header netCDF
// wrote for them.
struct ClassicOffsets {
    std::vector<uint64_t> begins;
    uint64_t file_id = 0;
};

ClassicOffsets classic_offsets(const NcOutput &nc, const std::vector<MpasField> &fields) {
    ClassicLayout layout;
    const std::string problem = read_classic_layout(nc.temporary_path(), layout);
    if (!problem.empty() || !layout.classic || layout.variables.size() != fields.size())
        fail(UM_ERR_IO, "MPAS mesh file: the header netCDF wrote to '", nc.temporary_path(),
             "' cannot be read back: ", problem.empty() ? "not the variables defined" : problem);
    ClassicOffsets offsets;
    for (size_t i = 0; i < fields.size(); ++i) {
        if (layout.variables[i].name != fields[i].name)
            fail(UM_ERR_INTERNAL, "MPAS mesh: variable ", i, " of the header is ", layout.variables[i].name,
                 ", not ", fields[i].name);
        offsets.begins.push_back(layout.variables[i].begin);
    }
    for (const ClassicLayout::Attribute &a : layout.global_attributes)
        if (a.name == "file_id" && a.bytes == std::strlen(kFileIdPlaceholder)) offsets.file_id = a.offset;
    if (offsets.file_id == 0) fail(UM_ERR_INTERNAL, "MPAS mesh: no file_id placeholder in the header");
    return offsets;
}

// Writes the file from `probe` (every variable present, the whole mesh's
// counts) and the blocks block_of makes, block_rows rows at a time: each
// block is written on the calling thread while the next is made in the
// context's arena. The netCDF lock is held while netCDF is called, not
// while progress is reported, so that the caller's progress callback is not
// deadlocked by it; file_id goes in last.
void write_blocks(Context &ctx, const MpasMesh &probe, const BlockOf &block_of, const std::string &path,
                  const MpasWriteOptions &options) {
    if (options.block_rows < 1) fail(UM_ERR_INTERNAL, "MPAS mesh: blocks of ", options.block_rows, " rows");
    const std::vector<MpasField> fields = dual::mpas_fields(probe);
    const std::vector<Rows> blocks = blocks_of(probe, options.block_rows);
    const int format = format_for(probe, fields, options);
    std::unique_lock<std::mutex> lock(netcdf_mutex());
    NcOutput nc(path, format, "MPAS mesh file");
    int old_fill = 0;
    nc.check(nc_set_fill(nc.id(), NC_NOFILL, &old_fill), "setting no-fill mode");
    std::vector<int> var_ids;
    define(nc, probe, fields, var_ids);
    nc.check(nc_enddef(nc.id()), "ending define mode");
    const bool through_netcdf = format == NC_NETCDF4;
    ClassicOffsets offsets;
    if (!through_netcdf) {
        nc.close_netcdf();  // the header, with the variables' offsets
        offsets = classic_offsets(nc, fields);
    }
    std::unique_ptr<DirectRegions> direct;
    if (!through_netcdf) {
        std::vector<uint64_t> ends;
        uint64_t total = 0;
        for (size_t i = 0; i < fields.size(); ++i) {
            ends.push_back(offsets.begins[i] + value_bytes(probe, fields[i]));
            total += value_bytes(probe, fields[i]);
        }
        if (total >= options.direct_min_bytes) direct = std::make_unique<DirectRegions>(nc.file(), offsets.begins, ends);
    }
    ValueWriter out(nc, var_ids, through_netcdf, offsets.begins, direct.get());
    std::vector<ByteStream> hashes = value_hashes_for(probe, fields);
    FileState file{out, fields, hashes, {}};
    try {
        lock.unlock();
        int64_t array_first[2] = {0, 0};
        const MpasMesh *made[2] = {nullptr, nullptr};
        if (!blocks.empty()) made[0] = &block_of(0, blocks[0], &array_first[0]);
        for (size_t b = 0; b < blocks.size(); ++b) {
            const int now = static_cast<int>(b % 2), next = 1 - now;
            ctx.alongside(
                [&] {
                    if (b + 1 < blocks.size()) made[next] = &block_of(next, blocks[b + 1], &array_first[next]);
                },
                [&] {
                    if (out.through_netcdf()) lock.lock();
                    put_block(file, *made[now], blocks[b], array_first[now]);
                    if (out.through_netcdf()) lock.unlock();
                    nc.start_writeback();
                });
            ctx.progress("MPAS mesh", 0.05 + 0.95 * double(b + 1) / double(blocks.size()));
        }
        lock.lock();
    } catch (...) {
        // The device thread is stopped first (it may be in a write and a
        // sync), not under the lock every netCDF call in the process waits on.
        direct.reset();
        if (!lock.owns_lock()) lock.lock();  // nc's destructor removes the partial file under the lock
        throw;
    }
    const std::string id = file_id_of(probe.radius_m, fields, finish(hashes, probe, fields));
    if (!through_netcdf) {  // netCDF has closed the file: no lock for the flush
        lock.unlock();
        if (direct) direct->finish();
        nc.file().write_at(offsets.file_id, id.data(), id.size());
        nc.commit();
        return;
    }
    nc.check(nc_redef(nc.id()), "reopening define mode");
    nc.put_text(NC_GLOBAL, "file_id", id);
    nc.check(nc_enddef(nc.id()), "ending define mode");
    nc.close();
}

}  // namespace

std::string mpas_file_id(const MpasMesh &m) {
    const std::vector<MpasField> fields = dual::mpas_fields(m);
    std::vector<ByteStream> hashes = value_hashes_for(m, fields);
    for (size_t i = 0; i < fields.size(); ++i) {
        if (fields[i].reals) hashes[i].feed(fields[i].reals->data(), fields[i].reals->size() * sizeof(double));
        if (fields[i].ints) hashes[i].feed(fields[i].ints->data(), fields[i].ints->size() * sizeof(int32_t));
    }
    return file_id_of(m.radius_m, fields, finish(hashes, m, fields));
}

void write_mpas_mesh(const MpasMesh &m, const std::string &path, const MpasWriteOptions &options) {
    for (const MpasField &f : dual::mpas_fields(m)) {
        size_t n = 1;
        for (MpasDim d : f.dims) n *= dim_length(m, d);
        size_t have = f.reals ? f.reals->size() : f.ints ? f.ints->size() : n;
        if (have != n)
            fail(UM_ERR_INTERNAL, "MPAS mesh: variable ", f.name, " has ", have,
                 " values instead of ", n);
    }
    Context serial;  // nothing to make: every block is already in m
    serial.set_threads(1);
    write_blocks(serial, m, [&](int, Rows, int64_t *array_first) -> const MpasMesh & {
        *array_first = 0;
        return m;
    }, path, options);
}

void write_mpas_mesh(Context &ctx, const dual::MpasSource &source, const std::string &path,
                     const MpasWriteOptions &options) {
    // Two blocks, each first the probe, so that every variable is present
    // in both.
    const MpasMesh probe = source.probe(ctx);
    MpasMesh block[2] = {probe, probe};
    write_blocks(ctx, probe, [&](int buffer, Rows rows, int64_t *array_first) -> const MpasMesh & {
        source.rows(ctx, rows.kind, rows.first, rows.count, block[buffer]);
        *array_first = rows.first;
        return block[buffer];
    }, path, options);
}

}  // namespace um::io
