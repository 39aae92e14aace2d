#!/usr/bin/env python3
"""Height of FlightGear's scenery surface at a point, read from a BTG file.

    python3 scripts/fg_scenery_elevation.py FILE.btg.gz LAT LON [METRES_NORTH ...]

FILE is one of the scenery's binary terrain files (e.g. an airport's
`Scenery/Terrain/w160n20/w160n21/PHLI.btg.gz` in FlightGear's data). The script finds
the triangle under (LAT, LON) and interpolates the height of its corners (WGS-84
ellipsoid, metres), printing it with the triangle's material (`pa_threshold`,
`pa_rest`, `Grass`, ...). Extra arguments repeat that the given distances north of
the point (a runway profile for the models, which roll north).

This is how the altitudes of `sim-cli --origin phli|bikf` were measured (docs/cli.md
"Named origins"). Python 3 standard library only. It reads BTG versions 7 to 10
(the object types it needs: bounding sphere, vertex list, triangle faces).
"""

import gzip
import math
import struct
import sys

A = 6378137.0
F = 1 / 298.257223563
E2 = F * (2 - F)


def ecef(lat, lon, h):
    la, lo = math.radians(lat), math.radians(lon)
    n = A / math.sqrt(1 - E2 * math.sin(la) ** 2)
    return ((n + h) * math.cos(la) * math.cos(lo), (n + h) * math.cos(la) * math.sin(lo),
            (n * (1 - E2) + h) * math.sin(la))


def height(x, y, z):
    """Ellipsoidal height of an ECEF point (iterated to convergence)."""
    p = math.hypot(x, y)
    lat = math.atan2(z, p * (1 - E2))
    for _ in range(10):
        n = A / math.sqrt(1 - E2 * math.sin(lat) ** 2)
        h = p / math.cos(lat) - n
        lat = math.atan2(z, p * (1 - E2 * n / (n + h)))
    n = A / math.sqrt(1 - E2 * math.sin(lat) ** 2)
    return p / math.cos(lat) - n


def read_btg(path):
    """(version, centre, vertices relative to the centre, triangles (i, j, k, material))."""
    d = gzip.open(path).read()
    header, = struct.unpack_from("<I", d, 0)
    if header >> 16 != 0x5347:  # "SG"
        raise ValueError(f"{path}: not a BTG file")
    version = header & 0xFFFF
    o = 8
    if version >= 10:
        count, = struct.unpack_from("<i", d, o)
        o += 4
    else:
        count, = struct.unpack_from("<H", d, o)
        o += 2
    centre, vertices, triangles = None, [], []
    for _ in range(count):
        if version >= 10:
            kind, nprops, nelems = struct.unpack_from("<BII", d, o)
            o += 9
        else:
            kind, nprops, nelems = struct.unpack_from("<BHH", d, o)
            o += 5
        mask, material = None, None
        for _ in range(nprops):
            ptype, nbytes = struct.unpack_from("<BI", d, o)
            o += 5
            value = d[o:o + nbytes]
            o += nbytes
            if ptype == 0:
                material = value.decode(errors="replace")
            elif ptype == 1:
                mask = value[0]
        for _ in range(nelems):
            nbytes, = struct.unpack_from("<I", d, o)
            o += 4
            b = d[o:o + nbytes]
            o += nbytes
            if kind == 0:  # bounding sphere: centre (3 doubles), radius
                centre = struct.unpack_from("<ddd", b, 0)
            elif kind == 1:  # vertex list: 3 floats each, relative to the centre
                vertices += [struct.unpack_from("<fff", b, i) for i in range(0, nbytes, 12)]
            elif kind == 10:  # triangle faces: one index per enabled array per corner
                m = 0x01 | 0x08 if mask is None else mask  # default: vertices, texcoords
                per_corner = bin(m & 0xFF).count("1")
                size, fmt = (4, "<I") if version >= 10 else (2, "<H")
                idx = [struct.unpack_from(fmt, b, i)[0]
                       for i in range(0, nbytes, per_corner * size)]
                triangles += [(idx[i], idx[i + 1], idx[i + 2], material)
                              for i in range(0, len(idx) - 2, 3)]
    return version, centre, vertices, triangles


def surface(btg, lat, lon):
    """[(height_m, material)] of the triangles under (lat, lon)."""
    _, c, vertices, triangles = btg
    la, lo = math.radians(lat), math.radians(lon)
    east = (-math.sin(lo), math.cos(lo), 0.0)
    north = (-math.sin(la) * math.cos(lo), -math.sin(la) * math.sin(lo), math.cos(la))
    p0 = ecef(lat, lon, 0.0)

    def plane(v):
        d = [v[i] + c[i] - p0[i] for i in range(3)]
        return (sum(d[i] * east[i] for i in range(3)), sum(d[i] * north[i] for i in range(3)))

    found = []
    for i, j, k, material in triangles:
        (ax, ay), (bx, by), (cx, cy) = plane(vertices[i]), plane(vertices[j]), plane(vertices[k])
        det = (by - cy) * (ax - cx) + (cx - bx) * (ay - cy)
        if det == 0:
            continue
        l1 = ((by - cy) * -cx + (cx - bx) * -cy) / det
        l2 = ((cy - ay) * -cx + (ax - cx) * -cy) / det
        l3 = 1 - l1 - l2
        if min(l1, l2, l3) >= -1e-9:
            point = [l1 * (vertices[i][n] + c[n]) + l2 * (vertices[j][n] + c[n])
                     + l3 * (vertices[k][n] + c[n]) for n in range(3)]
            found.append((height(*point), material))
    return found


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    path, lat, lon = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
    btg = read_btg(path)
    for north_m in [0.0] + [float(a) for a in sys.argv[4:]]:
        # Metres north to degrees of latitude on the ellipsoid (meridian radius).
        m = A * (1 - E2) / (1 - E2 * math.sin(math.radians(lat)) ** 2) ** 1.5
        here = lat + math.degrees(north_m / m)
        hits = surface(btg, here, lon)
        text = ", ".join(f"{h:.2f} m ({mat})" for h, mat in hits) or "no triangle here"
        print(f"{here:.8f} {lon:.8f} (+{north_m:g} m north): {text}")


if __name__ == "__main__":
    main()
