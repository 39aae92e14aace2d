"""Direction Rust -> Python: bind a UDP port on 127.0.0.1, print it, receive N
datagrams and print each one parsed by flightgear-python's fdm_v24 as a JSON
line (see fgnet_py_common). Usage: parse_udp.py N TIMEOUT_S"""

import json
import socket
import sys

from fgnet_py_common import container_to_json, layout
from flightgear_python.fdm_v24 import fdm_struct


def main():
    count, timeout = int(sys.argv[1]), float(sys.argv[2])
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(('127.0.0.1', 0))
    sock.settimeout(timeout)
    print(f'PORT {sock.getsockname()[1]}', flush=True)
    for _ in range(count):
        data, _ = sock.recvfrom(4096)
        parsed = fdm_struct.parse(data)  # Const(24) raises on a wrong version
        rebuilt = fdm_struct.build(dict(parsed))
        print(json.dumps({
            'len': len(data),
            'layout': layout(),
            'fields': container_to_json(parsed),
            'rebuild_equal': rebuilt == data,
        }), flush=True)


if __name__ == '__main__':
    main()
