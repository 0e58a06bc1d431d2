#include "case_file.hpp"

#include <filesystem>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "unimesh.h"

namespace {

namespace fs = std::filesystem;

struct CaseError {
    std::string message;
};

// A path of the case file, relative to the file's own folder.
std::string resolve(const fs::path &folder, const std::string &path) {
    fs::path p(path);
    return p.is_absolute() ? p.string() : (folder / p).lexically_normal().string();
}

std::string where(const toml::node &node) {
    std::ostringstream s;
    s << " (line " << node.source().begin.line << ")";
    return s.str();
}

std::string string_value(const toml::node &node, const std::string &key) {
    if (auto v = node.value<std::string>()) return *v;
    throw CaseError{"'" + key + "' must be a string" + where(node)};
}

// An option value as um_options_set_string reads it.
std::string option_text(const toml::node &node, const std::string &key) {
    if (auto v = node.as_integer()) return std::to_string(v->get());
    if (auto v = node.as_boolean()) return v->get() ? "1" : "0";
    if (auto v = node.as_floating_point()) {
        std::ostringstream s;
        s.precision(17);
        s << v->get();
        return s.str();
    }
    throw CaseError{"options." + key + " must be a number or a boolean" + where(node)};
}

// The array of file names under key (relative to the case file's folder)
// into files, unless the flag was given.
void file_list(const toml::table &t, const std::string &key, const fs::path &folder, bool given,
               std::vector<std::string> &files) {
    const toml::node *g = t.get(key);
    if (!g || given) return;
    const toml::array *list = g->as_array();
    if (!list) throw CaseError{"'" + key + "' must be an array of file names" + where(*g)};
    files.clear();
    for (const toml::node &item : *list) files.push_back(resolve(folder, string_value(item, key)));
}

void apply(const toml::table &t, const fs::path &folder, const GivenFlags &given, BuildArgs &a) {
    static const std::set<std::string> known = {"geometry", "passages", "domain", "kind", "spacing_km", "spacing_file",
                                                "spacing_preset", "threads", "optimise", "vtu", "jigsaw", "components",
                                                "mpas_format", "out", "surface", "options"};
    for (const auto &[key, node] : t) {
        const std::string k(key.str());
        if (!known.count(k))
            throw CaseError{"unknown key '" + k + "'" + where(node) +
                            "; known: geometry, passages, domain, kind, spacing_km, spacing_file, spacing_preset, threads, "
                            "optimise, vtu, jigsaw, components, mpas_format, out, surface, [options]"};
    }
    file_list(t, "geometry", folder, given.geometry, a.geometry);
    file_list(t, "passages", folder, given.passages, a.passages);
    file_list(t, "domain", folder, given.domain, a.domain);
    if (const toml::node *n = t.get("kind"); n && !given.kind) a.default_kind = string_value(*n, "kind");
    if (!given.spacing) {
        if (const toml::node *n = t.get("spacing_km")) {
            auto v = n->value<double>();
            if (!v || !(*v > 0)) throw CaseError{"'spacing_km' must be a number > 0" + where(*n)};
            a.spacing_km = *v;
        }
        if (const toml::node *n = t.get("spacing_file")) a.spacing_file = resolve(folder, string_value(*n, "spacing_file"));
        if (const toml::node *n = t.get("spacing_preset")) a.spacing_preset = string_value(*n, "spacing_preset");
    }
    if (const toml::node *n = t.get("threads"); n && !given.threads) {
        // as_integer, not value<int64_t>: toml++ would convert a float
        // (1e27, say) to an integer without a range check.
        const toml::value<int64_t> *v = n->as_integer();
        if (!v || v->get() < 0 || v->get() > 1024)
            throw CaseError{"'threads' must be an integer in [0, 1024]" + where(*n)};
        a.threads = static_cast<int>(v->get());
    }
    auto flag = [&](const char *key, bool given_too, bool &value) {
        const toml::node *n = t.get(key);
        if (!n || given_too) return;
        auto v = n->value<bool>();
        if (!v) throw CaseError{std::string("'") + key + "' must be true or false" + where(*n)};
        value = *v;
    };
    bool optimise = !a.no_optimise;
    flag("optimise", given.no_optimise, optimise);
    a.no_optimise = !optimise;
    flag("vtu", given.vtu, a.vtu);
    flag("jigsaw", given.jigsaw, a.jigsaw);
    flag("components", given.components, a.components);
    if (const toml::node *n = t.get("mpas_format"); n && !given.mpas_format) {
        a.mpas_format = string_value(*n, "mpas_format");
        if (a.mpas_format != "auto" && a.mpas_format != "netcdf4")
            throw CaseError{"'mpas_format' must be \"auto\" or \"netcdf4\", not \"" + a.mpas_format + "\"" + where(*n)};
    }
    if (const toml::node *n = t.get("surface"); n && !given.surface) {
        a.surface = string_value(*n, "surface");
        a.surface_source = "case key surface";
    }
    if (const toml::node *n = t.get("out"); n && !given.out) a.out_dir = resolve(folder, string_value(*n, "out"));
    if (const toml::node *n = t.get("options")) {
        const toml::table *opts = n->as_table();
        if (!opts) throw CaseError{"'options' must be a table" + where(*n)};
        std::string text;
        for (const auto &[key, value] : *opts) {
            // Each key must name an option by itself: "a=1;b" would pass two
            // options to um_options_set_string, and a misspelt one is the
            // case file's error (at its line), not --option's.
            const std::string name(key.str());
            um_option known = 0;
            if (name.find_first_of("=;") != std::string::npos || um_option_key(name.c_str(), &known) != UM_OK)
                throw CaseError{"options." + name + " is not a known option" + where(value)};
            text += name + "=" + option_text(value, name) + ";";
        }
        // Set before the command line's --option, which wins.
        a.case_options = text;
    }
}

}  // namespace

bool read_case_file(const std::string &path, const GivenFlags &given, BuildArgs &args, std::string *error) {
    try {
        toml::table t = toml::parse_file(path);
        apply(t, fs::path(path).parent_path(), given, args);
        return true;
    } catch (const toml::parse_error &e) {
        std::ostringstream s;
        // toml++ may describe a problem over several lines: one line here.
        std::string what(e.description());
        for (char &c : what)
            if (c == '\n' || c == '\r') c = ' ';
        s << "case file " << path << ": " << what << " (line " << e.source().begin.line << ")";
        *error = s.str();
    } catch (const CaseError &e) {
        *error = "case file " + path + ": " + e.message;
    }
    return false;
}
