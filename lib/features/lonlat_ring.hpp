// A closed ring drawn in longitude and latitude, as GeoJSON draws it and
// domain rings are traced (features/domain.hpp): the plane in which a
// domain ring's inside is decided, and a polygon's holes are checked.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace um::features {

class LonLatRing {
public:
    // The n points of a ring (not repeating the first), degrees. Its
    // longitudes are unwrapped along it, each edge the shorter way round;
    // through a pole, whose one point stands for an edge along it of any
    // longitude (a box up to lat 90 wider than 180 degrees runs 340
    // degrees west along its top), the longitude the ring would gain round
    // the pole is taken back there.
    LonLatRing(const double *lon, const double *lat, int64_t n);

    // Whether it goes round a pole (its longitudes unwrap by 360 degrees):
    // then it encloses nothing in this plane.
    bool round_a_pole() const;
    // Twice its signed area in the plane: positive counter-clockwise, the
    // region it encloses on its left.
    double twice_area() const;
    // Whether (lon, lat) lies inside it by the even-odd rule, lon taken as
    // the one of lon + 360 k within the ring's span (a ring not round a pole).
    bool encloses(double lon, double lat) const;

private:
    std::vector<double> lon_, lat_;  // n + 1 points: closed, the last unwrapped
};

// A domain ring drawn as GIS tools draw a polar cap: along a pole (two
// points at latitude 90 or -90, 360 degrees of longitude apart), along the
// antimeridian to a parallel (or a coast), round the sphere and back to
// the pole - in the plane the region between the ring and the pole. On the
// sphere its pole edge is one point and its two antimeridian edges one arc
// run both ways: the ring it stands for is the one round the pole.
// Whether the ring has an edge whose longitudes differ by 360 degrees or
// more (a cap, or a ring no other reading gives a meaning to).
bool runs_round_the_sphere(const double *lon, int64_t n);
// The ring round the pole such a ring stands for: its points (edges longer
// than 90 degrees of longitude cut, so that each runs the shorter way
// round, as rings are read) and the input point each comes from; or, in
// `error`, why the ring is no polar cap of that kind (a band round the
// sphere, a cap larger than a hemisphere: a ring round a pole holds the
// smaller side).
struct PolarCapRing {
    std::vector<double> lon, lat;
    std::vector<int64_t> source;
    std::string error;
};
PolarCapRing polar_cap_ring(const double *lon, const double *lat, int64_t n);

}  // namespace um::features
