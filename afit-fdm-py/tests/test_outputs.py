"""Outputs of a ``Flight`` (``acmi_to``, ``csv_to``, ``dis_to``,
``flightgear_to``): the run library's, written from Python to the same
bytes as ``sim-cli --acmi``, ``--csv``, ``--dis`` and ``--fg`` for the same
flight (``sim-cli`` run from the test), and read back by independent
readers pinned as the Rust interop tests pin them: pyacmi 1.2.4 for ACMI
(``fdm-run/tests/acmi_interop/read_acmi.py``), Open-DIS 1.0 for DIS
(``fdm-dis/tests/opendis_interop/decode_udp.py``) and flightgear-python
2.1.0 for FGNetFDM (its ``fdm_v24`` struct, as in
``fgnet/tests/fgnet_interop/parse_udp.py``). Those three live in their own
virtualenvs (Open-DIS pins an older NumPy): ``ACMI_PYTHON``, ``DIS_PYTHON``
and ``FGNET_PYTHON`` name their Pythons (``python_suite.rs`` sets them).
Missing, the tests fail; they never skip.
"""

from __future__ import annotations

import json
import math
import os
import pathlib
import socket
import subprocess
import threading
import zipfile
from typing import Callable, Dict, List, Sequence, Tuple

import pytest

import afit_fdm
from conftest import REPO, csv_rows

READ_ACMI = REPO / "fdm-run" / "tests" / "acmi_interop" / "read_acmi.py"
DECODE_UDP = REPO / "fdm-dis" / "tests" / "opendis_interop" / "decode_udp.py"

# Flights of both models: (sim-cli arguments, Flight keyword arguments,
# frames). Scripted climbs and turns with a trimmed start, so that every
# column and every ACMI field moves.
PALMER_SCRIPT = "1-60 throttle-up\n20-40 alpha-up\n100-130 bank-right\n200-215 bank-left\n"
BOURG_SCRIPT = "1-10 thrust-up\n5-25 pitch-up\n40-70 roll-right\n90-100 yaw-left\n"
CASES = {
    "palmer": (["--altitude-ft", "3000", "--speed-kt", "100", "--trim"],
               dict(altitude_ft=3000.0, speed_kt=100.0, trim=True), PALMER_SCRIPT, 300),
    "bourg": (["--altitude-ft", "4000", "--speed-kt", "90", "--trim"],
              dict(altitude_ft=4000.0, speed_kt=90.0, trim=True), BOURG_SCRIPT, 240),
}


def helper_python(var: str, package: str) -> str:
    python = os.environ.get(var)
    assert python, (
        f"{var} is not set: it names a Python with {package} (python_suite.rs sets it; "
        f"or `python3 -m venv v && v/bin/pip install {package}` and {var}=v/bin/python)"
    )
    return python


def run_cli(sim_cli: pathlib.Path, args: Sequence[str]) -> subprocess.CompletedProcess:
    proc = subprocess.run([str(sim_cli), *args], capture_output=True, text=True)
    assert proc.returncode == 0, f"sim-cli {' '.join(args)}: exit {proc.returncode}: {proc.stderr}"
    return proc


def cli_args(model: str, tmp: pathlib.Path) -> Tuple[List[str], afit_fdm.Flight, int]:
    """The case's sim-cli arguments (headless, its script written to ``tmp``)
    and the same flight from Python."""
    args, kwargs, script, frames = CASES[model]
    path = tmp / f"{model}.script"
    path.write_text(script, encoding="utf-8")
    full = [model, "--headless", "--fps", "30", "--frames", str(frames), "--script", str(path), *args]
    return full, afit_fdm.Flight(model, fps=30, script=script, **kwargs), frames


@pytest.mark.parametrize("model", ["palmer", "bourg"])
def test_csv_and_acmi_are_the_bytes_sim_cli_writes(sim_cli, tmp_path, model) -> None:
    args, flight, frames = cli_args(model, tmp_path)
    run_cli(sim_cli, [*args, "--csv", str(tmp_path / "cli.csv"), "--acmi", str(tmp_path / "cli.acmi")])
    flight.csv_to(tmp_path / "py.csv")
    flight.acmi_to(str(tmp_path / "py.acmi"))
    assert flight.outputs == [f"csv {tmp_path / 'py.csv'}", f"acmi {tmp_path / 'py.acmi'}"]
    flight.step(frames)
    flight.close_outputs()
    assert flight.outputs == []
    for name in ("csv", "acmi"):
        cli = (tmp_path / f"cli.{name}").read_bytes()
        ours = (tmp_path / f"py.{name}").read_bytes()
        assert ours == cli, name
    # Closing twice, and stepping on without outputs, is harmless.
    flight.close_outputs()
    flight.step(3)


def test_zipped_acmi_origin_and_reference_time_as_sim_cli(sim_cli, tmp_path) -> None:
    args, flight, frames = cli_args("palmer", tmp_path)
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    cli_file, py_file = tmp_path / "cli" / "f.zip.acmi", tmp_path / "py" / "f.zip.acmi"
    run_cli(sim_cli, [*args, "--origin", "47.5,11.25,700", "--acmi", str(cli_file),
                      "--acmi-reference-time", "2026-12-02T10:00:00.5Z"])
    flight.acmi_to(py_file, origin=(47.5, 11.25, 700.0), reference_time="2026-12-02T10:00:00.5Z")
    flight.step(frames)
    flight.close_outputs()
    with zipfile.ZipFile(py_file) as z:
        assert z.namelist() == ["f.txt.acmi"]
        text = z.read("f.txt.acmi").decode()
    assert "0,ReferenceLongitude=11\n0,ReferenceLatitude=48\n" in text
    assert py_file.read_bytes() == cli_file.read_bytes()


def read_acmi(path: pathlib.Path) -> Tuple[Dict[str, str], Dict[str, List[str]], List[Tuple[float, str, List[float]]]]:
    """What pyacmi reads: global properties, objects, per-frame samples."""
    python = helper_python("ACMI_PYTHON", "pyacmi==1.2.4")
    proc = subprocess.run([python, str(READ_ACMI), str(path)], capture_output=True, text=True,
                          env=dict(os.environ, PYTHONDONTWRITEBYTECODE="1"))
    assert proc.returncode == 0, proc.stderr
    header: Dict[str, str] = {}
    objects: Dict[str, List[str]] = {}
    samples = []
    t = math.nan
    for line in proc.stdout.splitlines():
        kind, _, rest = line.partition(" ")
        if kind == "H":
            k, _, v = rest.partition(" ")
            header[k] = v
        elif kind == "O":
            oid, _, info = rest.partition(" ")
            objects[oid] = info.split("\t")
        elif kind == "F":
            t = float(rest)
        elif kind == "P":
            words = rest.split(" ")
            samples.append((t, words[0], [float(w) for w in words[1:]]))
    return header, objects, samples


@pytest.mark.parametrize("model", ["palmer", "bourg"])
def test_pyacmi_reads_the_flight_the_csv_shows(tmp_path, model) -> None:
    """pyacmi reads every frame of the Python-written ACMI file within the
    file's rounding (1e-7 degrees, 1 cm, 0.01 degrees) of the CSV written
    beside it, as sim-cli's own interop test reads ``--acmi``; the clock goes
    on across a reset, and the flight after it is an object of its own
    (``100000001``: the first flight, ``1``, is removed at the reset)."""
    _, flight, frames = cli_args(model, tmp_path)
    flight.acmi_to(tmp_path / "f.acmi")
    flight.csv_to(tmp_path / "f.csv")
    flight.step(frames // 2)
    flight.reset()
    flight.step(frames // 2)
    flight.close_outputs()
    rows = csv_rows((tmp_path / "f.csv").read_text(encoding="utf-8"), model)
    assert len(rows) == 1 + frames // 2 + 1 + frames // 2
    header, objects, samples = read_acmi(tmp_path / "f.acmi")
    assert header["FileVersion"] == "2.2"
    name = "C172" if model == "palmer" else "Bourg 6-DoF"
    callsign = "C172-1" if model == "palmer" else "BRG-1"
    assert objects == {"1": [name, "Air+FixedWing", callsign],
                       "100000001": [name, "Air+FixedWing", callsign]}
    # The CSV row of each flown frame (rows after the reset's frame 0 follow
    # on the clock): row k is clock frame k, the reset's row shares the clock
    # of the frame before it.
    clock_rows: Dict[int, Dict[str, str]] = {}
    flown = 0
    for i, row in enumerate(rows):
        if i > 0 and row["frame"] != "0":
            flown += 1
        clock_rows[flown] = row
    by_frame = {round(t * 30): v for t, _, v in samples}
    assert set(by_frame) <= set(clock_rows) and len(by_frame) > frames // 2
    worst = [0.0, 0.0, 0.0]
    for k, v in by_frame.items():
        r = clock_rows[k]
        lon, lat, alt, roll, pitch, yaw = v
        d_deg = max(abs(lon - float(r["lon_deg"])), abs(lat - float(r["lat_deg"])))
        d_alt = abs(alt - float(r["alt_m"]))
        d_att = max(abs(roll - float(r["roll_deg"])), abs(pitch - float(r["pitch_deg"])),
                    abs(((yaw - float(r["fg_heading_deg"]) + 180.0) % 360.0) - 180.0))
        assert d_deg <= 0.5e-7 + 1e-12 and d_alt <= 0.005 + 1e-9 and d_att <= 0.005 + 1e-9, (k, v, r)
        worst = [max(worst[0], d_deg), max(worst[1], d_alt), max(worst[2], d_att)]
    # The flight moved: the comparison was not of a standing aircraft.
    assert worst[0] > 0.0 and worst[1] > 0.0


def capture(sock: socket.socket) -> List[bytes]:
    """Every datagram waiting on ``sock`` (loopback: all sent before this)."""
    sock.setblocking(False)
    out = []
    while True:
        try:
            out.append(sock.recv(65536))
        except BlockingIOError:
            return out


@pytest.mark.parametrize("model", ["palmer", "bourg"])
@pytest.mark.parametrize("every_frame", [True, False])
def test_dis_datagrams_are_the_bytes_sim_cli_sends(sim_cli, tmp_path, model, every_frame) -> None:
    args, flight, frames = cli_args(model, tmp_path)
    extra = ["--dis-every-frame"] if every_frame else []
    sink = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sink.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 21)
    sink.bind(("127.0.0.1", 0))
    target = f"127.0.0.1:{sink.getsockname()[1]}"
    with sink:
        proc = run_cli(sim_cli, [*args, "--json", "--dis", target, "--dis-entity", "12",
                                 "--dis-exercise", "3", *extra])
        cli = capture(sink)
        flight.dis_to(target, entity=12, exercise=3, every_frame=every_frame)
        flight.step(frames)
        report = flight.dis_report
        flight.close_outputs()
        ours = capture(sink)
    assert flight.dis_report is None
    assert len(cli) > 0 and ours == cli
    if every_frame:
        assert len(ours) == frames
    cli_report = json.loads(proc.stdout)["dis"]
    assert report == cli_report


def test_opendis_decodes_the_python_flight(tmp_path) -> None:
    """Open-DIS (an independent decoder) reads every PDU of a Python flight:
    its identity, type and marking, and its position and attitude within
    1e-6 degrees, 1 cm and 1e-4 degrees of the CSV's (the tolerances of
    sim-cli's own Open-DIS test)."""
    _, flight, frames = cli_args("palmer", tmp_path)
    python = helper_python("DIS_PYTHON", "opendis==1.0 numpy==1.26.4")
    decoder = subprocess.Popen([python, str(DECODE_UDP), str(frames), "20"], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True,
                               env=dict(os.environ, PYTHONDONTWRITEBYTECODE="1"))
    try:
        assert decoder.stdout is not None
        line = decoder.stdout.readline()
        assert line.startswith("PORT "), line + (decoder.stderr.read() if decoder.stderr else "")
        port = int(line.split()[1])
        flight.dis_to(f"127.0.0.1:{port}", site=7, application=8, entity=9, version=6,
                      every_frame=True, callsign="PY-9")
        flight.csv_to(tmp_path / "f.csv")
        # Fly in slices and wait for the decoder to print each slice's PDUs
        # before sending more: a burst of all frames can overflow the
        # decoder's socket buffer (about 200 datagrams by default on Linux)
        # while a loaded machine keeps the slow Python decoder behind, and
        # a datagram lost on loopback is then a timeout, not a bug of ours.
        lines: List[str] = []
        slice_frames = 30
        for start in range(0, frames, slice_frames):
            n = min(slice_frames, frames - start)
            flight.step(n)
            for _ in range(n):
                line = decoder.stdout.readline()
                assert line, "decoder ended early: " + (decoder.stderr.read() if decoder.stderr else "")
                lines.append(line)
        flight.close_outputs()
        rest, err = decoder.communicate(timeout=60)
        out = "".join(lines) + rest
    finally:
        if decoder.poll() is None:
            decoder.kill()
            decoder.wait()
    assert decoder.returncode == 0, err
    pdus = [json.loads(x) for x in out.splitlines()]
    rows = csv_rows((tmp_path / "f.csv").read_text(encoding="utf-8"), "palmer")
    assert len(pdus) == frames
    for i, pdu in enumerate(pdus):
        assert pdu["class"] == "EntityStatePdu"
        assert pdu["header"][0] == 6 and pdu["header"][1] == 1
        assert pdu["id"] == [7, 8, 9]
        assert pdu["type"] == [1, 2, 225, 85, 11, 1, 0]
        assert pdu["marking"] == "PY-9       "
        row = rows[i + 1]
        lat, lon, alt = pdu["lla"]
        roll, pitch, yaw = pdu["rpy_deg"]
        assert abs(lat - float(row["lat_deg"])) < 1e-6
        assert abs(lon - float(row["lon_deg"])) < 1e-6
        assert abs(alt - float(row["alt_m"])) < 0.01
        assert abs(roll - float(row["roll_deg"])) < 1e-4
        assert abs(pitch - float(row["pitch_deg"])) < 1e-4
        assert abs(((yaw - float(row["fg_heading_deg"]) + 180.0) % 360.0) - 180.0) < 1e-4


def test_reset_writes_frame_0_again_and_diverged_frames_are_left_out(sim_cli, tmp_path) -> None:
    """A reset writes a new frame-0 row (as sim-cli's interactive CSV); a
    diverged flight's CSV ends at the frame before the divergence, as
    sim-cli's, which stops there."""
    f = afit_fdm.Flight("bourg", fps=1, script="1-30 thrust-up\n")
    f.csv_to(tmp_path / "py.csv")
    f.step(2000)
    assert f.status == "diverged"
    f.close_outputs()
    (tmp_path / "s.txt").write_text("1-30 thrust-up\n", encoding="utf-8")
    proc = subprocess.run([str(sim_cli), "bourg", "--fps", "1", "--headless", "--frames", "2000",
                           "--script", str(tmp_path / "s.txt"), "--csv", str(tmp_path / "cli.csv")],
                          capture_output=True, text=True)
    assert proc.returncode == 1 and "diverged" in proc.stderr
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()

    g = afit_fdm.Flight("palmer")
    g.step(5)
    g.csv_to(tmp_path / "mid.csv")
    g.step(2)
    g.reset()
    g.step(1)
    g.close_outputs()
    mid = (tmp_path / "mid.csv").read_text().splitlines()
    assert mid[0] == "# model: palmer" and mid[1].startswith("frame,time_s,")
    frames = [line.split(",")[0] for line in mid[2:]]
    assert frames == ["5", "6", "7", "0", "1"]


def test_bad_output_arguments_raise_naming_them(tmp_path) -> None:
    f = afit_fdm.Flight("palmer")
    with pytest.raises(OSError, match="cannot create"):
        f.csv_to(tmp_path / "no" / "such" / "dir.csv")
    with pytest.raises(OSError, match="cannot create"):
        f.acmi_to(tmp_path / "no" / "such.acmi")
    with pytest.raises(ValueError, match="reference_time"):
        f.acmi_to(tmp_path / "a.acmi", reference_time="yesterday")
    with pytest.raises(ValueError, match="origin"):
        f.csv_to(tmp_path / "a.csv", origin=(91.0, 0.0, 0.0))
    with pytest.raises(TypeError, match="path"):
        f.csv_to(3)  # type: ignore[arg-type]
    for kwargs, name in [
        (dict(target="0.0.0.0:3000"), "unspecified"),
        (dict(target="127.0.0.1:0"), "port 0"),
        (dict(target="nonsense"), "target"),
        (dict(target="127.0.0.1:3000", entity=0), "entity"),
        (dict(target="127.0.0.1:3000", entity=65534), "entity"),
        (dict(target="127.0.0.1:3000", site=0), "site"),
        (dict(target="127.0.0.1:3000", application=65535), "application"),
        (dict(target="127.0.0.1:3000", exercise=0), "exercise"),
        (dict(target="127.0.0.1:3000", version=5), "version"),
        (dict(target="127.0.0.1:3000", dr="xyz"), "dr"),
        (dict(target="127.0.0.1:3000", heartbeat_s=0.0), "heartbeat_s"),
        (dict(target="127.0.0.1:3000", position_threshold_m=math.nan), "position_threshold_m"),
        (dict(target="127.0.0.1:3000", callsign="much too long a name"), "dis_to"),
    ]:
        with pytest.raises(ValueError, match=name):
            f.dis_to(**kwargs)
    assert f.outputs == [] and f.dis_report is None
    f.dis_to("127.0.0.1:3000")
    with pytest.raises(ValueError, match="already"):
        f.dis_to("127.0.0.1:3001")
    f.close_outputs()


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs Linux's /dev/full")
def test_an_output_that_fails_says_why_and_is_closed() -> None:
    """A CSV on a full disk (``/dev/full``: every write fails with ENOSPC):
    the step raises with the output's label, what failed and the system's
    reason (the source of the error, which the message used to leave out),
    the output is closed, and the flight flies on without it."""
    f = afit_fdm.Flight("palmer")
    f.csv_to("/dev/full")
    assert f.outputs == ["csv /dev/full"]
    with pytest.raises(ValueError) as raised:
        f.step(1000)
    message = str(raised.value)
    assert message.startswith("csv /dev/full: writing CSV file /dev/full: "), message
    assert "No space left on device" in message and message.endswith("(the output is closed)")
    assert f.outputs == []
    f.step(10)
    assert f.frame > 10


def capture_while(sock: socket.socket, work: Callable[[], None]) -> List[bytes]:
    """The datagrams ``sock`` receives while ``work()`` runs, drained by a
    thread as they come: a burst from a subprocess cannot be slowed down,
    and left in the socket it could overflow the receive buffer (a few
    hundred datagrams by default on Linux)."""
    got: List[bytes] = []
    done = threading.Event()

    def drain() -> None:
        while True:
            try:
                got.append(sock.recv(65536))
            except socket.timeout:
                if done.is_set():
                    return

    sock.settimeout(0.05)
    reader = threading.Thread(target=drain)
    reader.start()
    try:
        work()
    finally:
        done.set()
        reader.join()
    return got


def step_in_slices(flight: afit_fdm.Flight, frames: int) -> None:
    """``flight.step(frames)`` in slices of 10 frames, so that the draining
    thread of :func:`capture_while` runs between them: a step of fewer than
    256 frames holds the GIL, and one call's burst of datagrams could
    overflow the socket's buffer before the thread reads any (it did: 166
    of 240)."""
    for start in range(0, frames, 10):
        flight.step(min(10, frames - start))


def fg_sink() -> Tuple[socket.socket, str]:
    sink = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sink.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 21)
    sink.bind(("127.0.0.1", 0))
    return sink, f"127.0.0.1:{sink.getsockname()[1]}"


@pytest.mark.parametrize("model", ["palmer", "bourg"])
def test_flightgear_datagrams_are_the_bytes_sim_cli_sends(sim_cli, tmp_path, model) -> None:
    args, flight, frames = cli_args(model, tmp_path)
    sink, target = fg_sink()
    with sink:
        procs: List[subprocess.CompletedProcess] = []
        cli = capture_while(sink, lambda: procs.append(run_cli(sim_cli, [*args, "--json", "--fg", target])))

        def fly() -> None:
            flight.flightgear_to(target)
            assert flight.outputs == [f"flightgear {target}"]
            assert flight.flightgear_report == {"sent": 0, "failed": 0}
            step_in_slices(flight, frames)

        ours = capture_while(sink, fly)
        report = flight.flightgear_report
        flight.close_outputs()
    assert flight.flightgear_report is None and flight.outputs == []
    # One 408-byte datagram per flown frame, none for the start.
    assert len(cli) == frames and all(len(d) == 408 for d in cli)
    assert ours == cli
    assert report == json.loads(procs[0].stdout)["fg"] == {"sent": frames, "failed": 0}


FG_DECODE = """
import json, sys
from flightgear_python.fdm_v24 import fdm_struct
for line in sys.stdin:
    p = fdm_struct.parse(bytes.fromhex(line))  # Const(24) raises on another version
    print(json.dumps({k: p[k] for k in ("version", "lat_rad", "lon_rad", "alt_m", "phi_rad", "theta_rad", "psi_rad")}))
"""


def test_flightgear_python_decodes_the_python_flight(tmp_path) -> None:
    """flightgear-python's own FGNetFDM v24 struct (an independent decoder)
    reads every datagram of a Python flight: its position within 1e-6
    degrees and 1 cm of the CSV's (the datagram's latitude and longitude
    are f64 radians, its altitude f64 metres), its attitude within 1e-4
    degrees (f32 radians: about 1e-5 degrees of rounding)."""
    _, flight, frames = cli_args("bourg", tmp_path)
    python = helper_python("FGNET_PYTHON", "flightgear-python==2.1.0 construct==2.10.70")
    sink, target = fg_sink()
    with sink:

        def fly() -> None:
            flight.flightgear_to(target)
            flight.csv_to(tmp_path / "f.csv")
            step_in_slices(flight, frames)
            flight.close_outputs()

        datagrams = capture_while(sink, fly)
    assert len(datagrams) == frames
    decoded = subprocess.run([python, "-c", FG_DECODE], input="".join(d.hex() + "\n" for d in datagrams),
                             capture_output=True, text=True, timeout=120)
    assert decoded.returncode == 0, decoded.stderr
    fields = [json.loads(x) for x in decoded.stdout.splitlines()]
    rows = csv_rows((tmp_path / "f.csv").read_text(encoding="utf-8"), "bourg")
    assert len(fields) == frames
    for i, f in enumerate(fields):
        row = rows[i + 1]
        assert f["version"] == 24
        assert abs(math.degrees(f["lat_rad"]) - float(row["lat_deg"])) < 1e-6
        assert abs(math.degrees(f["lon_rad"]) - float(row["lon_deg"])) < 1e-6
        assert abs(f["alt_m"] - float(row["alt_m"])) < 0.01
        assert abs(math.degrees(f["phi_rad"]) - float(row["roll_deg"])) < 1e-4
        assert abs(math.degrees(f["theta_rad"]) - float(row["pitch_deg"])) < 1e-4
        yaw = math.degrees(f["psi_rad"]) - float(row["fg_heading_deg"])
        assert abs(((yaw + 180.0) % 360.0) - 180.0) < 1e-4


@pytest.mark.parametrize("target,message", [
    ("0.0.0.0:5500", "unspecified address"),
    ("255.255.255.255:5500", "broadcast address"),
    ("[::1]:5500", "IPv6 is not supported"),
    ("127.0.0.1", "missing port"),
    ("127.0.0.1:0", "not a decimal number in 1..65535"),
    ("0x7f.0.0.1:5500", "not a plain IPv4 address"),
])
def test_flightgear_targets_sim_cli_refuses_are_refused(target, message) -> None:
    flight = afit_fdm.Flight("palmer")
    with pytest.raises(ValueError, match=message):
        flight.flightgear_to(target)
    assert flight.outputs == [] and flight.flightgear_report is None


def test_a_flightgear_nobody_listens_to_is_counted_not_raised() -> None:
    """Sends to a closed loopback port fail with "connection refused" (the
    kernel's ICMP answer to an earlier datagram): counted, never raised;
    the flight flies on. A second link is refused until the first is closed."""
    sink, target = fg_sink()
    sink.close()
    flight = afit_fdm.Flight("palmer", altitude_ft=3000.0, speed_kt=100.0, trim=True)
    flight.flightgear_to(target)
    with pytest.raises(ValueError, match="already attached"):
        flight.flightgear_to(target)
    flight.step(10)
    report = flight.flightgear_report
    assert report is not None and report["sent"] + report["failed"] == 10 and report["failed"] >= 1
    assert flight.frame == 10
    flight.close_outputs()
    flight.flightgear_to(target)
    assert flight.outputs == [f"flightgear {target}"]


def test_a_file_the_flight_already_writes_is_refused(tmp_path: pathlib.Path) -> None:
    """Two of a flight's files at one path would overwrite each other's
    bytes (``sim-cli --csv F --acmi F`` is refused for that): ``csv_to``,
    ``acmi_to`` and ``record_to`` refuse a file the flight already writes,
    by the same path or another name (a symlink), with ``ValueError``
    naming the writer; nothing is attached and the first file is intact.
    Once that writer is closed, the path may be used again; ``/dev/null``
    clashes with nothing."""
    flight = afit_fdm.Flight("palmer", altitude_ft=3000.0, speed_kt=100.0, trim=True)
    csv, rec, acmi = tmp_path / "a.csv", tmp_path / "a.rec", tmp_path / "a.acmi"
    link = tmp_path / "link.csv"
    flight.csv_to(csv)
    link.symlink_to(csv)
    flight.record_to(rec)
    flight.acmi_to(acmi)
    flight.step(3)
    for attach, path, writer in [
        (flight.csv_to, csv, f"output `csv {csv}`"),
        (flight.acmi_to, link, f"output `csv {csv}`"),
        (flight.csv_to, rec, "recording"),
    ]:
        with pytest.raises(ValueError) as error:
            attach(path)
        assert str(error.value).endswith(f"{path} is already written by this flight's {writer}")
    assert flight.outputs == [f"csv {csv}", f"acmi {acmi}"] and flight.recording == str(rec)
    flight.step(2)
    flight.close_outputs()
    assert flight.stop_recording() == 5
    rows = csv_rows(csv.read_text(), "palmer")
    assert [r["frame"] for r in rows] == ["0", "1", "2", "3", "4", "5"]
    assert afit_fdm.replay(rec).frames == 5
    assert acmi.read_text().startswith("FileType=text/acmi/tacview")
    # A recording starts at frame 0: a new flight's, on its ACMI file.
    other = afit_fdm.Flight("bourg")
    other.acmi_to(tmp_path / "b.acmi")
    with pytest.raises(ValueError) as error:
        other.record_to(tmp_path / "b.acmi")
    assert str(error.value) == f"record_to: {tmp_path / 'b.acmi'} is already written by this flight's output `acmi {tmp_path / 'b.acmi'}`"
    assert other.recording is None
    # Outputs all on /dev/null (a caller discarding them) do not clash.
    null = afit_fdm.Flight("palmer")
    null.record_to("/dev/null")
    null.csv_to("/dev/null")
    null.acmi_to("/dev/null")
    null.step(40)
    null.close_outputs()
    assert null.stop_recording() == 40
    # Closed, the files may be written again (from the flight's frame on).
    flight.csv_to(link)
    flight.acmi_to(csv.with_suffix(".2.acmi"))
    assert flight.outputs == [f"csv {link}", f"acmi {csv.with_suffix('.2.acmi')}"]
