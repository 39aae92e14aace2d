"""Reads a Tacview ACMI file with pyacmi (PyPI `pyacmi`, pinned by the tests)
and prints every aircraft's track as pyacmi understands it, frame by frame.

    python read_acmi.py FILE

Output, one line each:
    H key value          global properties (ReferenceTime, FileVersion, ...)
    O id name<TAB>type<TAB>callsign   an object's declaration, when first seen
    F t                  a time frame (seconds, repr)
    P id lon lat alt roll pitch yaw   every live object at that frame (repr floats)
    R id t               the object was removed at time t
    E frames objects     the end

pyacmi's own line parser does the work (`Acmi.split_fields`,
`Acmi._parse_global_property`, `Acmi._parse_object_property`, its
`AcmiFileReader` and its zip detection); the frame loop is `Acmi.load_acmi`'s,
streamed so that a fleet of 10,000 aircraft over a minute fits in memory: after
each frame is printed, every field keeps only its latest value.
"""

import io
import sys
import zipfile

import pyacmi
from pyacmi.acmi import Acmi, AcmiFileReader, ACMI_FILE_ENCODING

FIELDS = ("Longitude", "Latitude", "Altitude", "Roll", "Pitch", "Yaw")


def main(path):
    acmi = Acmi()
    out = sys.stdout
    declared = set()
    removed = set()
    frames = 0

    def emit_frame(t):
        nonlocal frames
        frames += 1
        out.write("F %r\n" % t)
        for obj_id, obj in acmi.objects.items():
            if obj_id not in declared:
                declared.add(obj_id)
                out.write("O %s %s\n" % (obj_id, "\t".join([obj.name, obj.tags, obj.call_sign()])))
            if obj.removed_at is not None:
                if obj_id not in removed:
                    removed.add(obj_id)
                    out.write("R %s %r\n" % (obj_id, obj.removed_at))
                continue
            values = [obj.get_value(f, t) for f in FIELDS]
            out.write("P %s %s\n" % (obj_id, " ".join(repr(v) for v in values)))
            for f in FIELDS:
                d = obj.data.get(f)
                if d is not None and len(d) > 1:
                    key, value = d.peekitem(-1)
                    d.clear()
                    d[key] = value

    def parse(f):
        ar = AcmiFileReader(f)
        line = next(ar)
        assert line.startswith("FileType="), line
        out.write("H FileType %s\n" % line[len("FileType="):].strip())
        line = next(ar)
        assert line.startswith("FileVersion="), line
        out.write("H FileVersion %s\n" % line[len("FileVersion="):].strip())
        t = None
        for raw in ar:
            line = raw.strip()
            if not line or line.startswith("//"):
                continue
            if line.startswith("#"):
                if t is not None:
                    emit_frame(t)
                t = float(line[1:])
                acmi.timeframes.append(t)
                continue
            if line.startswith("-"):
                acmi.objects[acmi.parse_obj_id(line[1:])].removed_at = t
                continue
            fields = acmi.split_fields(line)
            obj_id = acmi.parse_obj_id(fields[0])
            if obj_id == "0":
                acmi._parse_global_property(fields)
            else:
                acmi._parse_object_property(obj_id, t, fields)
        if t is not None:
            emit_frame(t)

    if zipfile.is_zipfile(path):
        with zipfile.ZipFile(file=path) as z:
            names = z.namelist()
            assert len(names) == 1, names
            with z.open(names[0]) as f:
                parse(io.TextIOWrapper(f, encoding=ACMI_FILE_ENCODING))
    else:
        with open(path, "r", encoding=ACMI_FILE_ENCODING) as f:
            parse(f)
    out.write("H ReferenceTime %s\n" % acmi.reference_time.strftime("%Y-%m-%dT%H:%M:%SZ"))
    out.write("H ReferenceLongitude %r\n" % acmi.reference_longitude)
    out.write("H ReferenceLatitude %r\n" % acmi.reference_latitude)
    out.write("E %d %d\n" % (frames, len(acmi.objects)))
    out.flush()


if __name__ == "__main__":
    main(sys.argv[1])
