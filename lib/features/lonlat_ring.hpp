// A closed ring drawn in longitude and latitude, as GeoJSON draws it and
// domain rings are traced (features/domain.hpp): the plane in which a
// domain ring's inside is decided, and a polygon's holes are checked.
#pragma once

#include <cstdint>
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

}  // namespace um::features
