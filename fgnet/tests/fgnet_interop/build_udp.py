"""Direction Python -> Rust: read JSON lines from stdin, each {name: value} in
fgnet_py_common's encoding, build a datagram with flightgear-python's
fdm_v24.fdm_struct.build() and send it to 127.0.0.1:PORT. Prints the built
bytes as hex, one line per datagram. Usage: build_udp.py PORT"""

import json
import socket
import sys

from fgnet_py_common import json_to_build_dict
from flightgear_python.fdm_v24 import fdm_struct


def main():
    port = int(sys.argv[1])
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    for line in sys.stdin:
        if not line.strip():
            continue
        data = fdm_struct.build(json_to_build_dict(json.loads(line)))
        sock.sendto(data, ('127.0.0.1', port))
        print(data.hex(), flush=True)


if __name__ == '__main__':
    main()
