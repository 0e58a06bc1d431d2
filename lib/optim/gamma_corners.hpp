// The support of obtuse corners on Gamma (gamma_corners.cpp, shape phase):
// a vertex off Gamma where one fits, else a vertex on Gamma taken out.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <utility>
#include <vector>

#include "optim/mesh_state.hpp"

namespace um::optim::detail {

class GammaCorners {
public:
    explicit GammaCorners(MeshState &s) : s_(s) {}
    int64_t support_gamma_corners();

private:
    // An obtuse triangle with its corner on Gamma, and what a vertex put
    // there to support the corner is judged against.
    struct GammaCorner {
        int32_t triangle;       // its slot (where the insertion starts)
        int32_t b, p, q;        // the corner on Gamma and the triangle's other two vertices
        std::vector<int32_t> region;  // the closed stars of b, p, q (sorted): what may change
        std::vector<std::pair<int32_t, int32_t>> gamma_edges;  // the edges along Gamma there
        int obtuse_before;      // the obtuse triangles touching the region
    };
    // A trial of a corner vertex: its slot when kept, and the obtuse
    // triangles around it when it helps (else -1).
    struct CornerTrial {
        int32_t vertex = -1;
        int obtuse = -1;
    };
    CornerTrial try_corner_vertex(const Vec3 &at, const GammaCorner &corner, bool keep = true);
    enum class CornerChange { none, vertex_added, vertex_removed };
    CornerChange support_gamma_corner(const GammaCorner &corner, bool opposite_gamma, std::vector<uint8_t> &locked);
    int32_t keep_best_corner_vertex(const std::vector<Vec3> &sites, size_t from, size_t to, const GammaCorner &corner);
    std::vector<Vec3> corner_sites(const GammaCorner &corner) const;
    struct MovedVertex {  // a vertex as it was before a trial moved it
        int32_t v;
        Vec3 lifted;
        float h;
    };
    std::vector<int32_t> odt_step(int32_t v);
    std::vector<int32_t> relax_link(int32_t d, const GammaCorner &corner, std::vector<MovedVertex> &moved);
    int32_t try_corner_relocation(const Vec3 &at, const GammaCorner &corner, std::vector<uint8_t> &locked);
    int corner_vertex_helps(int32_t d, const GammaCorner &corner) const;
    bool try_gamma_vertex_removal(int32_t v, const GammaCorner &corner);
    bool has_triangle(int32_t a, int32_t b, int32_t c) const;

    MeshState &s_;
};

}  // namespace um::optim::detail
