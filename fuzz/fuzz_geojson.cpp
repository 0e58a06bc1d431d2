// libFuzzer target: the GeoJSON reader on arbitrary bytes. Every input must
// be read or refused with um::Error (a status and a message); anything else
// escaping - another exception, a crash, a sanitizer report - is a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.hpp"
#include "io/geojson.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    um::features::Network network;
    um::io::GeojsonOptions options;
    try {
        um::io::read_geojson_text(std::string_view(reinterpret_cast<const char *>(data), size), options,
                                  network, "fuzz input");
    } catch (const um::Error &) {
        // refused cleanly: the network must be as it was (empty)
        if (network.part_count() != 0) __builtin_trap();
    }
    return 0;
}
