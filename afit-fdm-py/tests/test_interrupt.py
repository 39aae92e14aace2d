"""Ctrl-C stops a study: ``afit_fdm.study`` flies with the GIL released but
looks at Python's pending signals every 20 ms, so a SIGINT raises
``KeyboardInterrupt`` out of it within a fraction of a second instead of when
the whole study has been flown. Long ``Flight.step`` and ``Fleet.step``
calls, and a Gymnasium task's ``Fleet.task_step`` of many frames, look at
the signals between chunks of frames (a fraction of a second of flying each)
in the same way, and so does the wait for the program at a named pipe's
other end (an output's reader, a study file's or recording's writer)."""

from __future__ import annotations

import os
import pathlib
import signal
import subprocess
import sys
import threading
import time
from typing import Any, Callable, List, Tuple

import pytest

import afit_fdm

# A study far too long to finish during the test: 2**20 runs of up to an
# hour of flight each (108,000 frames at 30 fps), climbing at full throttle
# from 5,000 ft so that no run ends early on the ground. Even at 10**9
# aircraft frames per second (more than ten times what the fleet flies on
# one core) it would take over 100 s (measured: 64 runs take 2.2 s on two
# threads, so the whole study hours); the test gives it 5 s after the signal.
LONG_STUDY = """
model = "palmer"
runs = 1048576
seed = 1
fps = 30
duration_s = 3600.0
measures = ["max_height_m"]
script = \"\"\"
1-20 throttle-up
\"\"\"

[initial]
altitude_ft = 5000.0
speed_kt = 70.0
trim = true
"""

# The child prints a line just before it starts the study, then flies it;
# an uncaught KeyboardInterrupt prints its traceback and (Python 3.8 and
# later) ends the process by SIGINT, a return code of -SIGINT. It installs
# Python's own SIGINT handler first: a Python started with SIGINT ignored
# (as a background job of a shell, or under some test runners, inherits it)
# keeps it ignored, and Ctrl-C would then do nothing anywhere.
CHILD = """
import signal
import sys
import afit_fdm
signal.signal(signal.SIGINT, signal.default_int_handler)
study = afit_fdm.Study.from_toml(sys.argv[1])
print("flying", flush=True)
afit_fdm.study(study, threads=2)
print("finished", flush=True)
"""

# Seconds allowed between the signal and the child's exit. The fly looks at
# its stop flag every 16 frames of a 1,024-run block (well under a
# millisecond of work per thread) and the calling thread looks at the
# signals every 20 ms; the rest is the interpreter's exit. 5 s leaves room
# for a machine loaded several times over its cores, and is still far below
# the study's length (over 100 s, see LONG_STUDY).
BOUND_S = 5.0


def interrupted_child(code: str, argument: str) -> Tuple[str, str]:
    """Runs ``code`` in a child Python with ``argument``, waits for its
    ``flying`` line and a second more (it is then inside the long call),
    sends it SIGINT and checks that it ended by it within ``BOUND_S``
    without finishing, from a ``KeyboardInterrupt``; returns its stdout and
    stderr. ``with`` closes the pipes and waits for the child however the
    test ends: a failed assertion leaves no open pipe to warn about later."""
    with subprocess.Popen(
        [sys.executable, "-c", code, argument],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    ) as child:
        try:
            assert child.stdout is not None
            assert child.stdout.readline() == "flying\n", child.communicate()
            time.sleep(1.0)
            assert child.poll() is None, "the call ended before the signal"
            sent = time.monotonic()
            child.send_signal(signal.SIGINT)
            stdout, stderr = child.communicate(timeout=BOUND_S)
            waited = time.monotonic() - sent
        finally:
            if child.poll() is None:
                child.kill()
    assert waited < BOUND_S
    assert "finished" not in stdout
    assert child.returncode == -signal.SIGINT, stderr
    assert "KeyboardInterrupt" in stderr
    return stdout, stderr


def test_study_is_interrupted_by_sigint_and_raises_keyboard_interrupt() -> None:
    # The study parses (what the child does first): a wrong file would make
    # the child fail for another reason.
    assert afit_fdm.Study.from_toml(LONG_STUDY).runs == 1048576
    _, stderr = interrupted_child(CHILD, LONG_STUDY)
    # Raised from the study call (line 8 of CHILD), out of the fly itself.
    assert 'File "<string>", line 8, in <module>' in stderr
    assert "fly_columns" in stderr


def test_study_without_signal_is_unchanged() -> None:
    """The interruptible fly gives the same bits as before: a small study
    flown through ``afit_fdm.study`` equals the same runs flown in two
    ranges and concatenated (both paths go through the same loop, so this
    checks that no run is lost or repeated when no signal comes)."""
    text = LONG_STUDY.replace("runs = 1048576", "runs = 40").replace(
        "duration_s = 3600.0", "duration_s = 2.0"
    )
    whole = afit_fdm.study(text, threads=2)
    study = afit_fdm.Study.from_toml(text)
    parts = afit_fdm.RunTable.concat([study.fly(0, 17, threads=1), study.fly(17, 40, threads=2)])
    assert len(whole) == 40
    assert whole.identical(parts)


# The child starts one aircraft (or a fleet of 1,000) and steps it (or flies
# one task step of) 10**12
# frames: days of flying (at 0.25 µs a frame, about 70 hours for the
# aircraft). After the signal it prints the frames flown, proving the state
# is whole frames the aircraft reached, then re-raises.
STEP_CHILD = """
import math
import signal
import sys
import afit_fdm
signal.signal(signal.SIGINT, signal.default_int_handler)
if sys.argv[1] == "flight":
    flying = afit_fdm.Flight("palmer", altitude_ft=5000.0, speed_kt=100.0, trim=True)
    time_s = lambda: flying.state["time_s"]
else:
    flying = afit_fdm.Fleet("bourg", 1000, altitude_ft=5000.0, speed_kt=90.0, trim=True)
    time_s = lambda: float(flying["time_s"][0])
print("flying", flush=True)
try:
    if sys.argv[1] == "task":
        import numpy as np
        n = 1000
        out = (np.full((n, 11), np.nan, np.float32), np.empty(n), np.empty(n, bool), np.empty(n, bool))
        zeros = np.zeros(n)
        flying.task_step(np.zeros((n, 5)), 10**12, "climb", zeros, zeros, np.zeros(n, np.int64), 10, *out)
    else:
        flying.step(10**12)
except KeyboardInterrupt:
    t = time_s()
    print("frames", round(t * 30), math.isfinite(t) and t > 0, flush=True)
    if sys.argv[1] == "task":
        print("observed", bool(np.isfinite(out[0]).all()), flush=True)
    raise
print("finished", flush=True)
"""


@pytest.mark.parametrize("what", ["flight", "fleet", "task"])
def test_a_long_step_is_interrupted_by_sigint_between_whole_frames(what: str) -> None:
    """``task``: a Gymnasium task's step (``Fleet.task_step``) of 10**12
    frames, which flies after its first stretch in stretches as
    ``Fleet.step`` does; after the signal its outputs and views show the
    frames flown."""
    stdout, _ = interrupted_child(STEP_CHILD, what)
    words = stdout.split()
    assert words[0] == "frames" and words[2] == "True", stdout
    # Flown for about a second (at least one chunk), far from the end.
    assert 1000 <= int(words[1]) < 10**9, stdout
    if what == "task":
        assert words[3:] == ["observed", "True"], stdout


# Named pipes. The child opens the named pipe argv[1] as argv[2] says, with
# no program at the other end: an output (csv_to, acmi_to, record_to) waits
# for a reader, an input (a study file, a recording) for a writer. Opening a
# pipe waits in open(2), which used to hold the thread with Ctrl-C doing
# nothing until the other program came; the wait now looks at the signals
# every 20 ms.
PIPE_CHILD = """
import signal
import sys
import afit_fdm
signal.signal(signal.SIGINT, signal.default_int_handler)
fifo, what = sys.argv[1].split("|")
flight = afit_fdm.Flight("palmer")
print("flying", flush=True)
if what == "csv_to":
    flight.csv_to(fifo)
elif what == "acmi_to":
    flight.acmi_to(fifo)
elif what == "record_to":
    flight.record_to(fifo)
elif what == "study":
    afit_fdm.Study(fifo)
else:
    afit_fdm.replay(fifo)
print("finished", flush=True)
"""


@pytest.mark.parametrize("what", ["csv_to", "acmi_to", "record_to", "study", "replay"])
def test_a_wait_for_a_named_pipe_is_interrupted_by_sigint(what: str, tmp_path: pathlib.Path) -> None:
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    interrupted_child(PIPE_CHILD, f"{fifo}|{what}")


def _in_thread(work: Callable[[], Any]) -> Tuple[threading.Thread, List[Any]]:
    """``work()`` on a daemon thread; its result (or exception) lands in
    the list returned."""
    out: List[Any] = []

    def run() -> None:
        try:
            out.append(work())
        except BaseException as e:  # noqa: BLE001 - handed to the test
            out.append(e)

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    return thread, out


def test_an_output_pipe_gets_the_files_bytes_once_its_reader_comes(tmp_path: pathlib.Path) -> None:
    """A CSV, ACMI file or recording written into a named pipe: the wait
    ends when a reader comes (here after 0.3 s), and the reader gets the
    bytes a regular file gets."""
    for what in ("csv_to", "acmi_to", "record_to"):
        fifo = tmp_path / f"{what}.pipe"
        os.mkfifo(fifo)
        file = tmp_path / f"{what}.file"

        def read_later(path: pathlib.Path = fifo) -> bytes:
            time.sleep(0.3)
            return path.read_bytes()

        reader, got = _in_thread(read_later)
        for target in (fifo, file):
            flight = afit_fdm.Flight("palmer", altitude_ft=3000.0, speed_kt=100.0, trim=True)
            getattr(flight, what)(target)
            flight.step(45)
            if what == "record_to":
                flight.stop_recording()
            flight.close_outputs()
        reader.join(timeout=20)
        assert not reader.is_alive(), what
        assert got == [file.read_bytes()], what


def test_an_output_refused_is_refused_before_the_wait_for_a_reader(tmp_path: pathlib.Path) -> None:
    """What an output refuses (a recording not at the start, a file the
    flight already writes) is refused at once, also for a named pipe that
    no program reads: not after a reader came."""
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    flight = afit_fdm.Flight("palmer")
    flight.step(3)
    thread, out = _in_thread(lambda: flight.record_to(fifo))
    thread.join(timeout=10)
    assert not thread.is_alive(), "record_to waited for a reader before refusing"
    assert isinstance(out[0], ValueError) and "call reset() first" in str(out[0]), out


def test_an_input_pipe_is_read_once_its_writer_comes(tmp_path: pathlib.Path) -> None:
    """A study file and a recording read from named pipes: the same as from
    regular files once a writer comes (here after 0.3 s)."""
    flight = afit_fdm.Flight("palmer", altitude_ft=3000.0, speed_kt=100.0, trim=True)
    recording = tmp_path / "r.rec"
    flight.record_to(recording)
    flight.step(30)
    flight.stop_recording()
    text = LONG_STUDY.replace("runs = 1048576", "runs = 4")
    for name, data in (("study", text.encode()), ("replay", recording.read_bytes())):
        fifo = tmp_path / f"{name}.pipe"
        os.mkfifo(fifo)

        def write_later(path: pathlib.Path = fifo, data: bytes = data) -> None:
            time.sleep(0.3)
            path.write_bytes(data)

        writer, done = _in_thread(write_later)
        if name == "study":
            assert afit_fdm.Study(fifo).text == afit_fdm.Study.from_toml(text).text
        else:
            assert afit_fdm.replay(fifo).same_final_state is True
        writer.join(timeout=20)
        assert done == [None], name


# A named pipe whose reader opened it and takes nothing: once the pipe is
# full (64 KiB on Linux, a few hundred frames of CSV), a write into it waits,
# and Rust retries a write a signal interrupts. The child steps with the
# output on; the step waits in the write long before the signal comes (a
# second after "flying"). argv[2] "long" is one step of 10**9 frames (the
# GIL released); "short" is steps of 100 frames (the GIL held) in a loop.
# After the KeyboardInterrupt it prints the frames flown and what is still
# attached: the output the signal stopped is closed.
STALLED_PIPE_CHILD = """
import os
import signal
import sys
import afit_fdm
signal.signal(signal.SIGINT, signal.default_int_handler)
fifo, what, how = sys.argv[1].split("|")
reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
flight = afit_fdm.Flight("palmer", altitude_ft=5000.0, speed_kt=100.0, trim=True)
getattr(flight, what)(fifo)
print("flying", flush=True)
try:
    if how == "long":
        flight.step(10**9)
    else:
        while True:
            flight.step(100)
except KeyboardInterrupt:
    print("frames", flight.frame, flight.outputs, flight.recording, flush=True)
    raise
print("finished", flush=True)
"""


@pytest.mark.parametrize(
    "what,how",
    [("csv_to", "long"), ("csv_to", "short"), ("acmi_to", "long"), ("record_to", "long")],
)
def test_a_write_waiting_for_a_stalled_pipe_is_interrupted_by_sigint(
    what: str, how: str, tmp_path: pathlib.Path
) -> None:
    """Ctrl-C while a step waits to write into a pipe its reader does not
    read: ``KeyboardInterrupt`` within the bound, the frames flown stay
    flown, and the output (or recording) is closed."""
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    stdout, stderr = interrupted_child(STALLED_PIPE_CHILD, f"{fifo}|{what}|{how}")
    words = stdout.split()
    assert words[0] == "frames", stdout
    # The pipe took a few hundred frames before it was full; not all 10**9.
    assert 1 <= int(words[1]) < 10**6, stdout
    assert words[2:] == ["[]", "None"], stdout
    assert "Traceback" in stderr and "OSError" not in stderr and "ValueError" not in stderr


def test_a_signal_whose_handler_does_not_raise_lets_the_waiting_write_go_on(
    tmp_path: pathlib.Path,
) -> None:
    """A signal while a step waits to write into a full pipe runs its
    handler; one that does not raise lets the write go on, and the reader,
    once it reads, gets the bytes a regular file gets (none lost or written
    twice, also where a signal cut a write short)."""
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    file = tmp_path / "file.csv"
    handled: List[int] = []

    def handle(number: int, frame: Any) -> None:
        handled.append(number)

    previous = signal.signal(signal.SIGUSR1, handle)
    try:

        def signal_then_read() -> Tuple[List[bool], bytes]:
            """Three signals, each once the handler has run for the one
            before (while the step still waits: nothing reads yet), then
            the reading; whether each handler ran within 5 s, and the
            bytes."""
            time.sleep(0.5)
            in_time = []
            for i in range(3):
                os.kill(os.getpid(), signal.SIGUSR1)
                deadline = time.monotonic() + 5.0
                while len(handled) <= i and time.monotonic() < deadline:
                    time.sleep(0.01)
                in_time.append(len(handled) > i)
            return in_time, fifo.read_bytes()

        # The reader opens the pipe now (the output's wait for it ends) and
        # reads nothing until the signals have come.
        fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
        reader, got = _in_thread(signal_then_read)
        for target in (fifo, file):
            flight = afit_fdm.Flight("palmer", altitude_ft=3000.0, speed_kt=100.0, trim=True)
            flight.csv_to(target)
            # About 3 MB of rows, far more than the pipe holds: the step
            # waits for the reader (and the signals come) in its middle.
            flight.step(12_000)
            flight.close_outputs()
            if target == fifo:
                os.close(fd)
        reader.join(timeout=30)
        assert not reader.is_alive()
    finally:
        signal.signal(signal.SIGUSR1, previous)
    assert handled == [signal.SIGUSR1] * 3
    assert got == [([True, True, True], file.read_bytes())]
