#!/usr/bin/env python3
"""A map of an MPAS mesh from unimesh, and the lines it was built to follow.

    plot_mesh.py mesh.nc mesh.png [features.geojson ...]

Top: the globe (longitude-latitude), or for a regional mesh the box around
its cells, each cell coloured by its size (sqrt(areaCell), km), the input
coastlines (black) and rivers (blue) over it.
Bottom: a zoom on the region where the input lines are densest (without
them, where the cells are smallest), with the cells' edges, the ocean cells
(cellOceanMask) shaded blue and the land ones tan, and the input lines.
Uses Debian's python3-matplotlib and python3-netcdf4, without a display.
"""
import json
import math
import sys

from plot_signal import arguments_when_told

# Exit status 3: matplotlib, numpy or netCDF4 is missing (the caller's hint
# names the packages); any other failure is reported on stderr as it is.
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: E402  (the backend is chosen first)
    from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
    from matplotlib.colors import LogNorm, Normalize  # noqa: E402
    from matplotlib.ticker import FuncFormatter  # noqa: E402
    import netCDF4  # noqa: E402
    import numpy as np  # noqa: E402
except ImportError as e:
    print(f"plot_mesh.py: {e}", file=sys.stderr)
    sys.exit(3)

# The zoom shows about this many cells across.
ZOOM_CELLS_ACROSS = 30
# A mesh whose cells cover less than this share of the sphere is regional:
# the map shows the box around its cells, not the globe.
REGIONAL_SHARE = 0.99


def wrap(lon):
    """Longitudes in degrees into [-180, 180)."""
    return (np.asarray(lon) + 180.0) % 360.0 - 180.0


def read_lines(paths):
    """The input lines as (lon, lat, is_river) arrays, from GeoJSON files.

    Points are skipped (a passage given as a point has no line to draw)."""
    lines = []

    def add(coordinates, river):
        xy = np.asarray([c[:2] for c in coordinates if len(c) >= 2], dtype=float)
        if len(xy) >= 2:
            lines.append((xy[:, 0], xy[:, 1], river))

    for path in paths:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
        features = data.get("features", [data]) if isinstance(data, dict) else []
        for feature in features:
            if not isinstance(feature, dict):
                continue
            # (A bare geometry at the top level is its own feature.)
            geometry = feature.get("geometry") if feature.get("type") == "Feature" else feature
            geometry = geometry if isinstance(geometry, dict) else {}
            properties = feature.get("properties") if isinstance(feature.get("properties"), dict) else {}
            river = properties.get("kind") == "river"
            kind, coordinates = geometry.get("type"), geometry.get("coordinates") or []
            if kind == "LineString":
                add(coordinates, river)
            elif kind in ("MultiLineString", "Polygon"):
                for line in coordinates:
                    add(line, river)
            elif kind == "MultiPolygon":
                for polygon in coordinates:
                    for line in polygon:
                        add(line, river)
    return lines


def polylines(lines, river, lon0=0.0):
    """The rivers (or the rest) as polylines, longitudes within 180 degrees
    of lon0, each cut where it crosses the far side (lon0 + 180): one path
    per polyline, not per segment (a path per segment took most of the
    drawing time of a coastline mesh)."""
    out = []
    for lon, lat, is_river in lines:
        if is_river != river:
            continue
        lon = lon0 + wrap(lon - lon0)
        cuts = np.nonzero(np.abs(np.diff(lon)) >= 180.0)[0] + 1
        for x, y in zip(np.split(lon, cuts), np.split(lat, cuts)):
            if len(x) >= 2:
                out.append(np.stack([x, y], 1))
    return out


# Longitude ticks of a map centred away from 0, named from -180 to 180.
LONGITUDE_TICKS = FuncFormatter(lambda x, _: f"{x - 360 if x > 180 else x + 360 if x < -180 else x:g}")


def draw_lines(ax, lines, width, lon0=0.0):
    ax.add_collection(LineCollection(polylines(lines, False, lon0), colors="black", linewidths=width))
    ax.add_collection(LineCollection(polylines(lines, True, lon0), colors="tab:blue", linewidths=width))


def read_mesh(path):
    with netCDF4.Dataset(path) as d:
        d.set_auto_mask(False)
        radius = float(getattr(d, "sphere_radius", 6371229.0))
        mesh = {name: d[name][:] for name in ("lonCell", "latCell", "lonVertex", "latVertex", "areaCell",
                                               "nEdgesOnCell", "verticesOnCell", "cellsOnVertex")}
        mesh["ocean"] = d["cellOceanMask"][:] if "cellOceanMask" in d.variables else None
    for name in ("lonCell", "latCell", "lonVertex", "latVertex"):
        mesh[name] = np.degrees(mesh[name])
    mesh["lonCell"], mesh["lonVertex"] = wrap(mesh["lonCell"]), wrap(mesh["lonVertex"])
    # (areaCell is in sphere_radius units squared: metres on the Earth, else
    # a unit sphere, scaled to the Earth's mean radius.)
    metres_per_unit = 1.0 if radius > 1000.0 else 6371220.0 / radius
    mesh["size_km"] = np.sqrt(mesh["areaCell"]) * metres_per_unit / 1000.0
    mesh["regional"] = float(mesh["areaCell"].sum()) / (4.0 * math.pi * radius * radius) < REGIONAL_SHARE
    return mesh


# Above this many cells the map is drawn as an image of the cells' sizes
# (GLOBE_PIXELS across), not triangle by triangle: a figure about 1000 pixels
# wide shows no more, and drawing a million triangles took 8 s of the 30 km
# run's 20.
RASTER_CELLS = 200_000
GLOBE_PIXELS = 1440


def map_box(mesh):
    """(lon0, (x0, x1, y0, y1)): the longitude the map centres on and the box
    it shows, in longitudes within 180 degrees of lon0 and latitudes: the
    globe for a whole sphere, else the box around the cells' corners with a
    margin (centred on their mean longitude: a box across the dateline stays
    in one piece)."""
    if not mesh["regional"]:
        return 0.0, (-180.0, 180.0, -90.0, 90.0)
    lon = np.radians(mesh["lonCell"])
    lon0 = math.degrees(math.atan2(float(np.sin(lon).mean()), float(np.cos(lon).mean())))
    x, y = lon0 + wrap(mesh["lonVertex"] - lon0), mesh["latVertex"]
    margin = 0.03 * max(float(x.max() - x.min()), float(y.max() - y.min()), 0.01)
    return lon0, (max(lon0 - 180.0, float(x.min()) - margin), min(lon0 + 180.0, float(x.max()) + margin),
                  max(-90.0, float(y.min()) - margin), min(90.0, float(y.max()) + margin))


def size_image(mesh, lon0, box):
    """The mean cell size per pixel of an image of the box (GLOBE_PIXELS
    along its longer side); a pixel no cell centre falls in takes the mean
    of the smallest of the aligned blocks of 2^k x 2^k pixels holding it
    that holds one (a pyramid of block sums: a few passes over the image,
    where spreading the neighbours' means one pixel a pass took most of a
    second). Blocks do not wrap at the dateline. On a regional mesh a pixel
    whose block is wider than two of the largest cells is outside it (NaN)."""
    x0, x1, y0, y1 = box
    long_side = max(x1 - x0, y1 - y0)
    width = max(1, round(GLOBE_PIXELS * (x1 - x0) / long_side))
    height = max(1, round(GLOBE_PIXELS * (y1 - y0) / long_side))
    regional = mesh["regional"]
    if not regional:
        width, height = GLOBE_PIXELS, GLOBE_PIXELS // 2
    x = lon0 + wrap(mesh["lonCell"] - lon0)
    col = np.clip(((x - x0) / (x1 - x0) * width).astype(np.int64), 0, width - 1)
    row = np.clip(((mesh["latCell"] - y0) / (y1 - y0) * height).astype(np.int64), 0, height - 1)
    at = row * width + col
    total = np.bincount(at, weights=mesh["size_km"], minlength=width * height).reshape(height, width)
    count = np.bincount(at, minlength=width * height).reshape(height, width).astype(float)
    image = total / np.maximum(count, 1.0)
    # (A pixel is shortest east-west at the box's highest latitude.)
    km_per_pixel = 111.2 * (y1 - y0) / height * max(0.05, math.cos(math.radians(max(abs(y0), abs(y1)))))
    widest = 2.0 * float(mesh["size_km"].max()) / km_per_pixel + 1.0  # pixels
    rows, cols = np.nonzero(count == 0)
    level = 0
    while len(rows) > 0 and count.size > 1:
        total, count = halved(total), halved(count)
        level += 1
        r, c = rows >> level, cols >> level
        found = count[r, c] > 0
        outside = regional and 2**level > widest
        image[rows[found], cols[found]] = np.nan if outside else total[r[found], c[found]] / count[r[found], c[found]]
        rows, cols = rows[~found], cols[~found]
    if regional:
        image[rows, cols] = np.nan
    return np.ma.masked_invalid(image)


def halved(a):
    """Sums of 2 x 2 blocks (a row or column of zeros added to an odd side)."""
    a = np.pad(a, ((0, a.shape[0] % 2), (0, a.shape[1] % 2)))
    return a.reshape(a.shape[0] // 2, 2, a.shape[1] // 2, 2).sum(axis=(1, 3))


def draw_globe(ax, fig, mesh, lines):
    """The globe, or a regional mesh's box, each cell coloured by its size."""
    size = mesh["size_km"]
    low, high = float(size.min()), float(size.max())
    norm = LogNorm(low, high) if high > 3.0 * low else Normalize(low, max(high, low * 1.0001))
    lon0, box = map_box(mesh)
    if len(size) > RASTER_CELLS:
        shaded = ax.imshow(size_image(mesh, lon0, box), origin="lower", extent=box, norm=norm,
                           cmap="viridis", interpolation="nearest")
    else:
        triangles = mesh["cellsOnVertex"].astype(np.int64) - 1
        triangles = triangles[(triangles >= 0).all(axis=1)]
        lon, lat = lon0 + wrap(mesh["lonCell"] - lon0), mesh["latCell"]
        span = lon[triangles].max(axis=1) - lon[triangles].min(axis=1)
        triangles = triangles[span < 180.0]  # (those across the far side would smear the map)
        shaded = ax.tripcolor(lon, lat, triangles, facecolors=size[triangles].mean(axis=1), norm=norm,
                              cmap="viridis", shading="flat", rasterized=True)
    draw_lines(ax, lines, 0.25, lon0)
    ax.set_xlim(box[0], box[1]), ax.set_ylim(box[2], box[3])
    if not mesh["regional"]:
        ax.set_aspect("equal")
    else:  # (degrees of longitude shortened as at the box's middle latitude)
        ax.set_aspect(1.0 / max(0.2, math.cos(math.radians(0.5 * (box[2] + box[3])))))
    ax.xaxis.set_major_formatter(LONGITUDE_TICKS)
    ax.set_title(f"{len(size):,} cells, coloured by size")
    fig.colorbar(shaded, ax=ax, shrink=0.8, label="cell size sqrt(areaCell), km")


def zoom_centre(mesh, lines):
    """Where the input lines are densest (5-degree bins; on a regional mesh,
    bins holding a cell: its lines go beyond it), else the smallest cells."""
    if lines:
        lon = wrap(np.concatenate([x for x, _, _ in lines]))
        lat = np.concatenate([y for _, y, _ in lines])
        bins, extent = (72, 36), ((-180, 180), (-90, 90))
        counts, lon_edges, lat_edges = np.histogram2d(lon, lat, bins=bins, range=extent)
        if mesh["regional"]:
            cells, _, _ = np.histogram2d(mesh["lonCell"], mesh["latCell"], bins=bins, range=extent)
            counts[cells == 0] = 0
    if lines and counts.max() > 0:
        i, j = np.unravel_index(np.argmax(counts), counts.shape)
        inside = (lon >= lon_edges[i]) & (lon <= lon_edges[i + 1]) & (lat >= lat_edges[j]) & (lat <= lat_edges[j + 1])
        return float(np.median(lon[inside])), float(np.median(lat[inside]))
    smallest = np.argmin(mesh["size_km"])
    return float(mesh["lonCell"][smallest]), float(mesh["latCell"][smallest])


def draw_zoom(ax, mesh, lines):
    lon0, lat0 = zoom_centre(mesh, lines)
    lon, lat = mesh["lonCell"], mesh["latCell"]
    dlon = wrap(lon - lon0)
    near = (np.abs(lat - lat0) < 5.0) & (np.abs(dlon) * math.cos(math.radians(lat0)) < 5.0)
    size_km = float(np.median(mesh["size_km"][near])) if near.any() else float(np.median(mesh["size_km"]))
    half_lat = min(20.0, max(0.02, 0.5 * ZOOM_CELLS_ACROSS * size_km / 111.2))
    half_lon = min(60.0, half_lat / max(0.2, math.cos(math.radians(lat0))))
    shown = np.nonzero((np.abs(dlon) < 1.2 * half_lon) & (np.abs(lat - lat0) < 1.2 * half_lat))[0]
    polygons, colours = [], []
    for c in shown:
        corners = mesh["verticesOnCell"][c, : mesh["nEdgesOnCell"][c]].astype(np.int64) - 1
        corners = corners[corners >= 0]
        xy = np.stack([lon0 + wrap(mesh["lonVertex"][corners] - lon0), mesh["latVertex"][corners]], 1)
        polygons.append(xy)
        ocean = mesh["ocean"] is not None and mesh["ocean"][c] > 0
        colours.append("#cfe3f5" if ocean else "#efe4cc")
    ax.add_collection(PolyCollection(polygons, facecolors=colours, edgecolors="0.35", linewidths=0.3))
    draw_lines(ax, lines, 0.8, lon0)
    ax.set_xlim(lon0 - half_lon, lon0 + half_lon), ax.set_ylim(lat0 - half_lat, lat0 + half_lat)
    ax.set_aspect(1.0 / max(0.2, math.cos(math.radians(lat0))))
    ax.set_title(f"around ({lon0:.2f}, {lat0:.2f}): cells of about {size_km:.3g} km "
                 f"(ocean blue, land tan){', the input lines' if lines else ''}")
    ax.xaxis.set_major_formatter(LONGITUDE_TICKS)
    ax.set_xlabel("longitude"), ax.set_ylabel("latitude")


def main(argv):
    if len(argv) < 3:
        print("usage: plot_mesh.py mesh.nc mesh.png [features.geojson ...]", file=sys.stderr)
        return 2
    mesh = read_mesh(argv[1])
    lines = read_lines(argv[3:])
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(11, 12), gridspec_kw={"height_ratios": [1, 1.1]})
    draw_globe(top, fig, mesh, lines)
    draw_zoom(bottom, mesh, lines)
    fig.tight_layout()
    try:
        fig.savefig(argv[2], dpi=110)
    except OSError as e:
        print(f"plot_mesh.py: cannot write {argv[2]}: {e.strerror}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(arguments_when_told(sys.argv)))
