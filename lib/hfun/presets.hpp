// The named spacings E3SM uses for its global ocean meshes, with the formulas
// of MPAS-Tools (mpas_tools.mesh.creation.mesh_definition_tools):
//   "QU<km>"            quasi-uniform: h = km everywhere (e.g. QU240);
//   "EC<km>to<km>"      EC_CellWidthVsLat, eddy-closure: the coarser number is
//                       cellWidthMidLat, the finer cellWidthEq, the other
//                       parameters at their defaults (e.g. EC60to30; E3SM's
//                       newer spelling EC30to60 gives the same);
//   "RRS<km>to<km>"     RRS_CellWidthVsLat, Rossby-radius scaling: the coarser
//                       number is cellWidthEq, the finer cellWidthPole (e.g.
//                       RRS18to6, or RRS6to18).
// Prefixes are ASCII case-insensitive; numbers are decimal (e.g. QU7.5), > 0.
#pragma once

#include <string_view>

#include "hfun/spacing.hpp"

namespace um::hfun {

// The parameters of EC_CellWidthVsLat, with its defaults (EC60to30).
struct EcParameters {
    double cell_width_eq = 30.0;      // km at the equator
    double cell_width_mid_lat = 60.0; // km at mid-latitudes
    double cell_width_pole = 35.0;    // km at the poles
    double lat_pos_eq = 15.0;         // degrees: centre of the equatorial transition
    double lat_pos_pole = 73.0;       // degrees: centre of the polar transition
    double lat_transition = 40.0;     // degrees: equatorial -> polar formula
    double lat_width_eq = 6.0;        // degrees: width of the equatorial transition
    double lat_width_pole = 9.0;      // degrees: width of the polar transition
};

// Cell width in km at a latitude in degrees (mesh_definition_tools.EC_CellWidthVsLat).
double ec_cell_width_km(double lat_deg, const EcParameters &p = {});
// Cell width in km at a latitude in degrees (mesh_definition_tools.RRS_CellWidthVsLat).
double rrs_cell_width_km(double lat_deg, double cell_width_eq, double cell_width_pole);

// The spacing of a preset name (see the top of this file); an unknown or
// malformed name is UM_ERR_INVALID_ARGUMENT with the accepted forms.
SpacingPtr make_preset(std::string_view name);

}  // namespace um::hfun
