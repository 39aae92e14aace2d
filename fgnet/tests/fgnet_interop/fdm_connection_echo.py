"""flightgear-python's real receive path: an FDMConnection(fdm_version=24)
receiving on an ephemeral 127.0.0.1 port and sending every datagram straight
back (callback returns the parsed container unchanged) to 127.0.0.1:PORT.
FDMConnection applies fg_util.fix_fg_radian_parsing to every received
datagram before the callback, so the echo shows exactly what the library does
to angles. Prints 'PORT n', runs until stdin closes. Usage: fdm_connection_echo.py PORT"""

import sys

from flightgear_python.fg_if import FDMConnection


def echo(fdm_data, event_pipe):
    return fdm_data


def main():
    back_port = int(sys.argv[1])
    conn = FDMConnection(fdm_version=24, rx_timeout_s=60.0)
    conn.connect_rx('127.0.0.1', 0, echo)
    conn.connect_tx('127.0.0.1', back_port)
    port = conn.fg_rx_sock.getsockname()[1]
    conn.start()
    print(f'PORT {port}', flush=True)
    sys.stdin.read()  # the Rust test closes stdin when done
    conn.stop()


if __name__ == '__main__':
    main()
