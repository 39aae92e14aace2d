"""Builds DIS 7 Entity State PDUs with Open-DIS (the PyPI package `opendis`)
and sends them to 127.0.0.1:PORT, for our listener to decode.

Usage: build_udp.py PORT

Reads one JSON object per line on stdin: `lla` (degrees, degrees, metres),
`rpy_deg` (roll, pitch, yaw relative to local NED), `id`, `marking`. The
ECEF location and DIS Euler angles come from opendis's
`RangeCoordinates.GPS().llarpy2ecef`. Prints each datagram as hex.
"""

import io
import json
import math
import socket
import sys

from opendis.DataOutputStream import DataOutputStream
from opendis.dis7 import EntityStatePdu
from opendis.RangeCoordinates import GPS


def main():
    port = int(sys.argv[1])
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    gps = GPS()
    for line in sys.stdin:
        req = json.loads(line)
        lat, lon, alt = req["lla"]
        roll, pitch, yaw = (math.radians(a) for a in req["rpy_deg"])
        x, y, z, psi, theta, phi = gps.llarpy2ecef(
            math.radians(lat), math.radians(lon), alt, roll, pitch, yaw
        )
        pdu = EntityStatePdu()
        pdu.protocolVersion = 7
        pdu.exerciseID = 1
        pdu.pduType = 1
        pdu.protocolFamily = 1
        pdu.length = 144
        # opendis 1.0 defaults pduStatus to a PduStatus record but serialises
        # it as one unsigned byte, which fails; set the byte itself.
        pdu.pduStatus = 0
        pdu.padding = 0
        pdu.entityID.siteID, pdu.entityID.applicationID, pdu.entityID.entityID = req["id"]
        pdu.forceId = 1
        et = pdu.entityType
        et.entityKind, et.domain, et.country, et.category = 1, 2, 225, 85
        et.subcategory, et.specific, et.extra = 11, 1, 0
        pdu.entityLocation.x, pdu.entityLocation.y, pdu.entityLocation.z = x, y, z
        o = pdu.entityOrientation
        o.psi, o.theta, o.phi = psi, theta, phi
        pdu.deadReckoningParameters.deadReckoningAlgorithm = 2
        pdu.marking.characterSet = 1
        pdu.marking.setString(req["marking"])
        pdu.entityAppearance = 0
        pdu.capabilities = 0
        buf = io.BytesIO()
        pdu.serialize(DataOutputStream(buf))
        data = buf.getvalue()
        sock.sendto(data, ("127.0.0.1", port))
        print(data.hex(), flush=True)


if __name__ == "__main__":
    main()
