"""Receives DIS datagrams on 127.0.0.1 and decodes them with Open-DIS (the
PyPI package `opendis`), independently of dis-rs.

Usage: decode_udp.py COUNT TIMEOUT_S

Prints `PORT n` once bound, then one JSON line per datagram with every
Entity State field as opendis parsed it, plus opendis's own conversions:
`RangeCoordinates.GPS().ecef2lla` (latitude/longitude in degrees, height in
metres) and `GPS().ecef2llarpy` (roll/pitch/yaw of the body relative to
local NED, radians). Floats are printed with repr, so they are exact.
"""

import json
import math
import socket
import sys

from opendis.PduFactory import createPdu
from opendis.RangeCoordinates import GPS


def main():
    count, timeout = int(sys.argv[1]), float(sys.argv[2])
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", 0))
    sock.settimeout(timeout)
    print("PORT", sock.getsockname()[1], flush=True)
    gps = GPS()
    for _ in range(count):
        data, _addr = sock.recvfrom(8192)
        pdu = createPdu(data)
        loc = pdu.entityLocation
        ori = pdu.entityOrientation
        lat, lon, alt = gps.ecef2lla((loc.x, loc.y, loc.z))
        _lat, _lon, _alt, roll, pitch, yaw = gps.ecef2llarpy(
            loc.x, loc.y, loc.z, ori.psi, ori.theta, ori.phi
        )
        dr = pdu.deadReckoningParameters
        vec = lambda v: [v.x, v.y, v.z]
        et = pdu.entityType
        out = {
            "len": len(data),
            "class": type(pdu).__name__,
            "header": [pdu.protocolVersion, pdu.exerciseID, pdu.pduType,
                       pdu.protocolFamily, pdu.timestamp, pdu.length],
            "id": [pdu.entityID.siteID, pdu.entityID.applicationID, pdu.entityID.entityID],
            "force": pdu.forceId,
            "type": [et.entityKind, et.domain, et.country, et.category,
                     et.subcategory, et.specific, et.extra],
            "velocity": vec(pdu.entityLinearVelocity),
            "location": [loc.x, loc.y, loc.z],
            "orientation": [ori.psi, ori.theta, ori.phi],
            "dr_algorithm": dr.deadReckoningAlgorithm,
            "acceleration": vec(dr.entityLinearAcceleration),
            "angular_velocity": vec(dr.entityAngularVelocity),
            "marking_set": pdu.marking.characterSet,
            "marking": pdu.marking.charactersString(),
            "lla": [lat, lon, alt],
            "rpy_deg": [math.degrees(roll), math.degrees(pitch), math.degrees(yaw)],
        }
        print(json.dumps(out), flush=True)


if __name__ == "__main__":
    main()
