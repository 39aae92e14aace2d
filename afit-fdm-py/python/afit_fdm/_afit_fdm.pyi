"""Type stubs and API reference of the ``afit_fdm._afit_fdm`` extension module."""

import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "Flight",
    "Fleet",
    "_Study",
    "Replay",
    "replay",
    "RecordingError",
    "RecordingCutError",
    "ReplayDivergedError",
    "summarize_columns",
    "_math_atan2",
    "_math_hypot",
    "STATUS_CODES",
    "MODELS",
    "MAX_FPS",
    "__version__",
]

__version__: str

MODELS: Dict[str, Dict[str, Any]]
"""Per model name (``"palmer"``, ``"bourg"``): ``title``, ``state_fields``
(names with units), ``controls`` (``(name, low, high)`` triples) and
``actions`` (script action names)."""

MAX_FPS: int
"""The highest frame rate a flight, fleet or environment takes (10000):
``fps`` is a whole number in ``1..=MAX_FPS``."""

# A number: Python's, or NumPy's float16/float32/float64, integer or bool
# (a longdouble is refused at run time: its conversion would drop digits).
_Number = Union[float, int, np.floating[Any], np.integer[Any], np.bool_]
_PerAircraft = Union[_Number, npt.NDArray[np.float64]]

@final
class Flight:
    """One aircraft, flown frame by frame exactly as ``sim-cli`` flies it.

    ``model`` is ``"palmer"`` or ``"bourg"``; ``fps`` a whole number 1..=10000
    (``dt = 1/fps`` in the model's float type). Without ``altitude_ft``,
    ``speed_kt``, ``heading_deg`` and ``trim`` the start is the thesis's
    (Palmer at rest on the runway; Bourg 2000 ft up at 60 ft/s); with any of
    them the aircraft starts level at those conditions (the others from the
    model's own start), trimmed when ``trim=True`` (Palmer's throttle and
    angle of attack; Bourg's thrust, pitch and pitch trim). Keyword controls
    set the controls at frame 0: Palmer ``throttle`` (0..1), ``alpha_deg``
    (-16..20), ``bank_deg`` (-20..20), ``flaps_deg`` (0, 20 or 40),
    ``brakes`` (0 or 1: the wheel brakes, docs/palmer-model.md); Bourg
    ``thrust_lb`` (0..3000), ``landing_flaps`` (0 or 1), ``pitch_trim``
    (-1..1). ``script`` is a control script's text (``START-END action`` lines,
    docs/cli.md). Bad values raise ``ValueError``/``TypeError`` naming the
    argument.
    """

    def __new__(
        cls,
        model: str,
        *,
        fps: int = 30,
        altitude_ft: Optional[float] = None,
        speed_kt: Optional[float] = None,
        heading_deg: Optional[float] = None,
        trim: bool = False,
        script: Optional[str] = None,
        **controls: _Number,
    ) -> "Flight": ...
    def step(self, n: int = 1, actions: Optional[Sequence[str]] = None) -> None:
        """Steps ``n`` frames. Each frame: the model's start of frame (Bourg's
        rudder, ailerons and elevators back to neutral), the script's actions
        for the frame, then ``actions`` (names as in scripts, e.g.
        ``"thrust-up"``), then the model's step, the ground contact and the
        status. A crashed aircraft stays at rest; a step that would give a
        non-finite state is not kept and the status becomes ``"diverged"``.

        From 256 frames on, the GIL is released, and Ctrl-C (a signal whose
        handler raises, ``KeyboardInterrupt`` by default) stops the step
        between two chunks of 65,536 frames: it is raised, and the frames
        flown so far stay flown (the same bits as a shorter step). A step of
        any length whose output waits for a named pipe's reader is stopped
        by it there (see the outputs, below)."""
    def copy(self) -> "Flight":
        """An independent flight where this one is: the same model, frame,
        state, controls, status, script (and the place in it) and start, so
        a :meth:`reset` of the copy goes back to the same start. Stepped
        alike, the two fly the same bits as this flight alone would (a
        branch point for Monte Carlo runs or tree search). The recording and
        the outputs are not copied (their files and sockets stay this
        flight's): the copy has none, and its :meth:`record_to` refuses or
        takes a file as this flight's would (a recording starts at the
        start). ``copy.copy`` and ``copy.deepcopy`` call it.

        ``pickle`` makes the same copy across processes (``multiprocessing``,
        Ray): a flight pickles as its model, frame rate, script text, start,
        state, controls, status and frame counts, the numbers as their bits
        (a package of another pickle format refuses it by name). Unpickling
        bytes that are not such a flight (damaged, cut, or with numbers no
        flight has: a state that is not finite, controls out of range)
        raises ``ValueError``. As with any pickle, unpickle only data you
        trust."""
    def __copy__(self) -> "Flight": ...
    def __deepcopy__(self, memo: Any) -> "Flight": ...
    def __reduce__(self) -> Tuple[Any, Tuple[bytes]]: ...
    @classmethod
    def _from_pickle(cls, data: bytes) -> "Flight": ...
    def reset(self) -> None:
        """Back to the start: state, controls, status, frame 0. The recording
        and the outputs take the reset (``ValueError`` if writing it fails)."""
    def set_controls(self, **controls: _Number) -> None:
        """Sets controls by name, validated as in the constructor."""
    @property
    def model(self) -> str: ...
    @property
    def frame(self) -> int:
        """Frames stepped since the start or the last reset."""
    @property
    def fps(self) -> float: ...
    @property
    def dt_s(self) -> float:
        """The time step, s (Bourg's float32 widened exactly)."""
    @property
    def time_s(self) -> float:
        """Simulated time, s."""
    @property
    def state(self) -> Dict[str, float]:
        """The model's own state by name, units in the names: Palmer
        ``time_s, x_m, y_m, z_m, vx_mps, vy_mps, vz_mps`` (x north, y west, z
        up); Bourg ``time_s, x_ft .. vz_ftps``, body velocity ``u_ftps, v_ftps,
        w_ftps``, body rates ``p_radps, q_radps, r_radps``, the attitude
        quaternion ``qw, qx, qy, qz``, ``stalling`` (0/1), and the derived
        ``speed_ftps, euler_x_deg, euler_y_deg, euler_z_deg`` (the model's own
        Euler angles). Bourg's float32 values are widened exactly."""
    @property
    def controls(self) -> Dict[str, float]:
        """The controls now, by name (Bourg adds the per-frame surfaces
        ``elevator``, ``aileron``, ``rudder``: -1, 0 or +1, +1 being
        pitch-up, roll-right, yaw-right)."""
    @property
    def view(self) -> Dict[str, Union[float, bool]]:
        """The models' common view, SI units, shared earth frame (x north, y
        west, z up): ``time_s, x_m, y_m, z_m, vx_mps, vy_mps, vz_mps,
        roll_deg, pitch_deg, heading_deg, u_mps, v_mps, w_mps, airspeed_mps,
        alpha_deg, beta_deg, flaps_norm, engine_running, engine_rpm,
        stalling``."""
    @property
    def status(self) -> str:
        """``on_ground``, ``airborne``, ``landed_safe``, ``landed_rough``,
        ``crashed`` or ``diverged``."""
    @property
    def status_code(self) -> int:
        """The status as an :class:`afit_fdm.Status` code."""
    @property
    def actions(self) -> List[str]:
        """The model's action names."""
    def record_to(
        self,
        path: Union[str, "os.PathLike[str]"],
        *,
        origin: Optional[Tuple[float, float, float]] = None,
    ) -> None:
        """Starts recording this flight to ``path`` (created or truncated)
        in the recording format of ``sim-cli --record`` (docs/recording.md):
        the header holds the model, its aircraft, ``fps``, ``origin`` and the
        flight's start (controls and state at frame 0); every later
        :meth:`step` records each frame's actions (the script's, then
        ``actions``, in order) and every :meth:`reset` a reset.
        :meth:`stop_recording` seals it (a flight dropped while recording is
        sealed too). ``sim-cli replay FILE`` and :func:`replay` fly it again
        to the same bits.

        ``origin`` is ``(lat_deg, lon_deg, alt_m)`` of the model's
        ``x, y, z = 0`` on WGS-84 (only outputs such as the CSV's
        ``lat_deg``/``lon_deg`` and ACMI use it; the model's state does not),
        by default ``sim-cli``'s: 39.8264, -84.0483, 251 m.

        What a recording cannot hold is refused, not approximated: a
        recording starts where the flight starts, so ``record_to`` raises
        ``ValueError`` after a step or :meth:`set_controls` (call
        :meth:`reset` first), and :meth:`set_controls` raises ``ValueError``
        while recording (a controls value is not an action; set the starting
        controls in the constructor, or fly ``actions``). ``ValueError`` for
        a file an output of the flight writes (see below). ``OSError`` when
        the file cannot be created."""
    def stop_recording(self) -> int:
        """Seals and closes the recording (its end marker carries the final
        state's fingerprint); returns the frames recorded, across resets.
        ``ValueError`` when not recording."""
    @property
    def recording(self) -> Optional[str]:
        """The path being recorded to, or ``None``."""

    # Outputs: the run library's (fdm_run::acmi, ::csv, ::dis), as sim-cli's
    # --acmi, --csv and --dis write them. Each takes the flight as it is when
    # attached (frame 0 for a fresh flight), then every frame a step flies
    # and every reset, until close_outputs(). A diverged frame is left out
    # (CSV, DIS) or removes the aircraft (ACMI), as in sim-cli, whose run
    # stops there. ``origin`` is (lat_deg, lon_deg, alt_m) of the model's
    # x, y, z = 0, by default sim-cli's (39.8264, -84.0483, 251 m). A write
    # that fails raises ValueError from step()/reset() naming the output,
    # which is then closed; the frame was flown. A file the flight already
    # writes (the recording's or another output's, by any name: a symlink or
    # hard link too) is refused with ValueError, as sim-cli refuses
    # --csv F --acmi F; once that writer is closed, the file may be used.
    # /dev/null clashes with nothing.
    #
    # A path that is a named pipe (FIFO), here and in record_to(): the call
    # waits for a program to open it for reading, and a step's write waits
    # while that program takes nothing and the pipe is full. Ctrl-C (a
    # signal whose handler raises) ends either wait: KeyboardInterrupt is
    # raised (not the output's error), the frames flown stay flown, and an
    # output or recording whose write it stopped is closed. A handler that
    # does not raise runs and the write goes on waiting.
    def acmi_to(
        self,
        path: Union[str, "os.PathLike[str]"],
        *,
        origin: Optional[Tuple[float, float, float]] = None,
        reference_time: Optional[str] = None,
        title: Optional[str] = None,
    ) -> None:
        """Writes the flight as Tacview ACMI 2.2 to ``path`` (created or
        truncated; zip-compressed when the name ends in ``.zip.acmi``), the
        bytes ``sim-cli MODEL --acmi path`` writes for the same flight
        (docs/cli.md, "Tacview ACMI"): object 1 with the model's name and
        callsign (``C172-1``, ``BRG-1``), times frames flown / fps (a reset
        does not turn the clock back; the flight after a reset is a new
        object, ``100000001``, then ``200000001``, ..., and the one it ends
        is removed). ``reference_time``: an ISO 8601 UTC
        time ``YYYY-MM-DDTHH:MM:SS[.f]Z`` (default 2000-01-01T00:00:00Z);
        ``title`` defaults to the model's name. ``OSError`` when the file
        cannot be created, ``ValueError`` for a bad ``reference_time``."""
    def csv_to(
        self,
        path: Union[str, "os.PathLike[str]"],
        *,
        origin: Optional[Tuple[float, float, float]] = None,
    ) -> None:
        """Writes a CSV row per frame to ``path`` (created or truncated), the
        bytes ``sim-cli MODEL --csv path`` writes (docs/cli.md, "CSV output"):
        the model line ``# model: NAME`` (pandas: ``read_csv(path,
        comment="#")``), then the header ``frame,time_s,x,y,z,vx,vy,vz,
        lat_deg,lon_deg,alt_m,roll_deg,pitch_deg,fg_heading_deg``, the
        model's own columns, ``status``;
        a row for the flight when attached, one per frame, a frame-0 row
        after each reset. Numbers in the shortest form that reads back to the
        same bits. ``OSError`` when the file cannot be created."""
    def flightgear_to(
        self,
        target: str,
        *,
        origin: Optional[Tuple[float, float, float]] = None,
    ) -> None:
        """Sends the flight to FlightGear's native-FDM socket at ``target``
        (``"HOST:PORT"``, e.g. ``"127.0.0.1:5500"``; FlightGear started with
        ``--fdm=null --native-fdm=socket,in,30,,5500,udp``): one FGNetFDM v24
        datagram (408 bytes) per flown frame, the datagrams
        ``sim-cli MODEL --fg target`` sends for the same flight (docs/cli.md,
        docs/fgnetfdm.md); none for a diverged frame. They go out as fast as
        :meth:`step` flies: to watch in real time, step one frame per
        1/fps seconds. The target is checked as ``sim-cli --fg`` checks it:
        ``ValueError`` for IPv6, the broadcast or unspecified address or bad
        syntax; ``OSError`` when the host does not resolve or the socket
        cannot be made. Sends that fail (nobody listening) are counted
        (:attr:`flightgear_report`), never raised. One link per flight."""
    @property
    def flightgear_report(self) -> Optional[Dict[str, int]]:
        """The FlightGear link's counts so far, the ``fg`` object of
        ``sim-cli --fg ... --json``: ``{"sent": n, "failed": n}``, or
        ``None`` without a link."""
    def dis_to(
        self,
        target: str,
        *,
        origin: Optional[Tuple[float, float, float]] = None,
        entity: int = 1,
        callsign: Optional[str] = None,
        site: int = 1,
        application: int = 1,
        exercise: int = 1,
        version: int = 7,
        dr: str = "rvw",
        position_threshold_m: float = 1.0,
        orientation_threshold_deg: float = 3.0,
        heartbeat_s: float = 5.0,
        every_frame: bool = False,
    ) -> None:
        """Publishes the flight as a DIS entity (Entity State PDUs over UDP,
        one per datagram) to ``target`` (``"HOST:PORT"``, unicast or
        broadcast, IPv4 or IPv6), the datagrams ``sim-cli MODEL --dis`` sends
        (docs/cli.md, docs/dis.md): entity ``site:application:entity``,
        marking ``callsign`` (at most 11 printable ASCII characters; default
        ``C172-N``/``BRG-N``, N the entity number), dead reckoning ``dr``
        (``fpw``, ``rpw``, ``rvw``, ``fvw``) with the thresholds, or a PDU
        every frame. Sends that fail are counted (:attr:`dis_report`), never
        raised. ``ValueError`` naming the argument for a bad setting;
        ``OSError`` when the socket cannot be made. One DIS output per
        flight."""
    @property
    def dis_report(self) -> Optional[Dict[str, Any]]:
        """The DIS output's counts so far, the ``dis`` object of
        ``sim-cli --json`` (``pdus``, ``bytes``, ``failed``, ``reasons``, ...),
        or ``None`` without a DIS output."""
    @property
    def outputs(self) -> List[str]:
        """The attached outputs, e.g. ``["acmi f.acmi", "csv f.csv"]``."""
    def close_outputs(self) -> None:
        """Finishes and detaches every output (ACMI: its last time line and
        the zip container; CSV: flushed; DIS, FlightGear: the socket
        closed). A flight
        dropped with outputs finishes them too. ``OSError`` naming the first
        output that could not be finished (all are finished)."""

class RecordingError(ValueError):
    """A recording that cannot be replayed: not a recording, another format
    version, a model this build does not have, truncated or corrupt (every
    block is checksummed). The message names the problem."""

class RecordingCutError(RecordingError):
    """A recording cut before its end marker, refused by :func:`replay` as
    ``sim-cli replay`` reports it: ``FILE: cut at byte B before its end
    marker; the N frames before the cut are intact ...``."""

    at_byte: int
    """Where the intact blocks end (the first byte of the missing, torn or
    damaged block)."""
    frames: int
    """Frames before the cut, across resets: what ``salvage=True`` flies."""

class ReplayDivergedError(ValueError):
    """A replay that stopped at a frame whose state is not finite, as
    ``sim-cli replay`` stops (its message: ``frame N: the MODEL model
    diverged (non-finite state) at dt = DT s``)."""

    frame: int
    """The diverged frame, since the start or the last reset."""
    replay: "Replay"
    """The replay up to that frame: its :attr:`Replay.flight` at the
    diverged frame (status ``diverged``, the last finite state), its
    trajectory without the diverged row (as ``sim-cli replay --csv``)."""

@final
class Replay:
    """What :func:`replay` read and flew."""

    @property
    def cut(self) -> Optional[Tuple[int, int]]:
        """With ``salvage=True``, for a cut recording: ``(at_byte, frames)``,
        where it was cut and the frames flown; ``None`` for a complete one."""

    @property
    def model(self) -> str: ...
    @property
    def fps(self) -> int:
        """Frames per second (a recording stores a whole number)."""
    @property
    def frames(self) -> int:
        """Frames flown, across resets."""
    @property
    def resets(self) -> int: ...
    @property
    def events(self) -> int:
        """Events stored: runs of identical frames (one per block they span) and resets."""
    @property
    def origin(self) -> Tuple[float, float, float]:
        """``(lat_deg, lon_deg, alt_m)`` from the header."""
    @property
    def same_final_state(self) -> Optional[bool]:
        """Whether the replay ended in the recorded flight's final state (the
        fingerprint of a format-3 recording: a hash of every bit of the
        state); ``None`` for versions 1 and 2, which have none."""
    @property
    def same_maths(self) -> Optional[bool]:
        """Whether the recording was made with this build's maths; ``None``
        without a fingerprint."""
    @property
    def flight(self) -> Flight:
        """The flight at the end of the replay: the recording's aircraft,
        ``fps`` and start (``reset()`` goes back to it), no script. It can
        fly on from there."""
    @property
    def trajectory(self) -> Optional[Dict[str, npt.NDArray[Any]]]:
        """With ``trajectory=True``: the rows ``sim-cli replay --csv`` writes
        (frame 0, one per frame, a new frame 0 after each reset) as columns:
        ``frame`` (int64, frames since the start or the last reset), the
        :attr:`Flight.state` fields, the :attr:`Flight.controls` fields
        (float64) and ``status`` (int64, :class:`afit_fdm.Status`)."""

def replay(
    source: Union[str, "os.PathLike[str]", bytes],
    *,
    trajectory: bool = False,
    salvage: bool = False,
) -> Replay:
    """Reads a recording (a file of at most 64 MiB, or its bytes) written by
    :meth:`Flight.record_to` or ``sim-cli --record`` (format versions 1, 2
    and 3), validates it whole and flies it again, with the GIL released:
    the same frames as ``sim-cli replay``, so the same bits.

    Raises :class:`RecordingError` (a ``ValueError``) for anything that is not
    an intact recording of a model this build has; ``OSError`` when the file
    cannot be read; ``ValueError`` when ``trajectory=True`` would hold more
    than 10 million rows. A recording cut before its end marker (its
    recording run killed, the machine stopped) raises
    :class:`RecordingCutError` with ``sim-cli replay``'s words; with
    ``salvage=True`` its intact frames are flown instead, as ``sim-cli
    replay`` flies them (:attr:`Replay.cut` says where it was cut). As
    ``sim-cli replay``, the replay stops at a frame whose state is not
    finite: :class:`ReplayDivergedError`."""

@final
class Fleet:
    """``n`` aircraft of one model, stepped together by the SIMD kernels
    (``precision="exact"``: every aircraft bit-identical to :class:`Flight`
    without script; ``"fast"``: Palmer only, within 1e-9).

    Start and control arguments are numbers (the same for every aircraft:
    Python's, or NumPy's float16, float32, float64, integers and bools, each
    taken exactly) or one-dimensional float64 arrays of shape ``(n,)`` (one
    each); the controls
    are Palmer's ``throttle, alpha_deg, bank_deg, flaps_deg, brakes`` or Bourg's
    ``thrust_lb, elevator, aileron, rudder, landing_flaps, pitch_trim``
    (the surfaces -1, 0 or +1 and held until changed: a fleet has no start-of-
    frame reset). Wrong types and dtypes raise ``TypeError``, wrong shapes,
    non-finite or out-of-range values ``ValueError``; both name the argument
    (and the first bad index). A refused call changes nothing. A fleet that
    does not fit in the memory this process can still allocate raises
    ``MemoryError`` at once, saying what it needs and what there is (as
    ``sim-cli fleet`` refuses it).

    **State views and their lifetime.** :attr:`state`, ``fleet[name]``,
    :attr:`columns` and :attr:`status` are read-only NumPy views of buffers
    the fleet writes in place at the end of every :meth:`step` and
    :meth:`reset` (and of the tasks' :meth:`task_step` and
    :meth:`task_observe`; ``task_step(..., views=False)`` refreshes only
    :attr:`status`); reading them never copies. A view stays valid (it keeps its
    buffer alive) after the fleet is gone, and then keeps its last values.
    Values change in place on the next step: copy (``np.array(view)``) what
    must be kept. Do not read a fleet's views in one thread while another
    thread steps that fleet.
    """

    def __new__(
        cls,
        model: str,
        n: int,
        *,
        fps: int = 30,
        precision: str = "exact",
        parallel: bool = True,
        altitude_ft: Optional[_PerAircraft] = None,
        speed_kt: Optional[_PerAircraft] = None,
        heading_deg: Optional[_PerAircraft] = None,
        trim: bool = False,
        **controls: _PerAircraft,
    ) -> "Fleet": ...
    def step(self, frames: int = 1) -> None:
        """Steps every aircraft ``frames`` frames (ground contact, touchdown,
        crash and divergence per aircraft), with the GIL released, then
        refreshes the views. ``parallel=True`` uses every core (rayon).

        Ctrl-C (a signal whose handler raises, ``KeyboardInterrupt`` by
        default) stops a long step between two chunks of frames (about
        2,000,000 aircraft-frames each): it is raised after the views are
        refreshed, and the frames flown so far stay flown. Cut or not, the
        frames are the same bits."""
    def reset(
        self,
        mask: Optional[npt.NDArray[np.bool_]] = None,
        *,
        altitude_ft: Optional[_PerAircraft] = None,
        speed_kt: Optional[_PerAircraft] = None,
        heading_deg: Optional[_PerAircraft] = None,
        trim: bool = False,
        **controls: _PerAircraft,
    ) -> None:
        """Restarts the aircraft where ``mask`` (bool, shape ``(n,)``) is
        true, all without it, as the constructor would start them."""
    def set_controls(
        self, mask: Optional[npt.NDArray[np.bool_]] = None, **controls: _PerAircraft
    ) -> None:
        """Sets controls of the aircraft where ``mask`` is true (all without it)."""
    def copy(self) -> "Fleet":
        """An independent fleet where this one is: the same model, size,
        ``fps``, precision and threading, every aircraft's state, controls
        and status bit for bit. Stepped alike, the two fly the same bits as
        this fleet alone would (a branch point for Monte Carlo studies or
        tree search). The copy's views are its own arrays, filled with the
        aircraft's current state (also after a ``task_step`` with
        ``views=False``); its :attr:`last_step_interval` is ``(0.0, 0.0)``.
        ``copy.copy`` and ``copy.deepcopy`` give this copy, and :mod:`pickle`
        (protocol 2 or later) carries it to another process (a Ray task, a
        ``multiprocessing`` worker). Unpickling checks what it reads and
        raises ``ValueError`` saying why for bytes that are not a pickled
        fleet of this package (cut or damaged bytes, another format, an
        unknown model or precision, a frame rate out of range, a state that
        is not finite, controls out of their ranges), and ``MemoryError``
        for more aircraft than this process can hold. As with any pickle,
        unpickle only data you trust."""
    def __copy__(self) -> "Fleet": ...
    def __deepcopy__(self, memo: Any) -> "Fleet": ...
    def __reduce__(self) -> Tuple[Any, Tuple[bytes]]: ...
    @classmethod
    def _from_pickle(cls, data: bytes) -> "Fleet": ...
    @property
    def state(self) -> Dict[str, npt.NDArray[np.float64]]:
        """State columns by name (read-only float64 views of shape ``(n,)``;
        the names of :attr:`Flight.state`)."""
    def __getitem__(self, name: str, /) -> npt.NDArray[np.float64]: ...
    @property
    def columns(self) -> npt.NDArray[np.float64]:
        """All state columns, shape ``(len(fields), n)``, read-only."""
    @property
    def status(self) -> npt.NDArray[np.uint8]:
        """Status codes (:class:`afit_fdm.Status`), read-only view."""
    @property
    def controls(self) -> Dict[str, npt.NDArray[np.float64]]:
        """The controls by name (new arrays)."""
    @property
    def fields(self) -> List[str]: ...
    @property
    def model(self) -> str: ...
    @property
    def fps(self) -> float: ...
    @property
    def precision(self) -> str: ...
    @property
    def instruction_set(self) -> str:
        """``x86-64-v4``, ``x86-64-v3`` or ``baseline``."""
    @property
    def last_step_interval(self) -> Tuple[float, float]:
        """``(start, end)`` of the last :meth:`step`'s work, seconds on a
        process-wide monotonic clock, measured in Rust with the GIL released."""
    def __len__(self) -> int: ...
    def task_step(
        self,
        actions: npt.ArrayLike,
        frames: int,
        task: str,
        target_alt_ft: npt.NDArray[np.float64],
        target_heading_deg: npt.NDArray[np.float64],
        steps: npt.NDArray[np.int64],
        max_steps: int,
        obs: npt.NDArray[np.float32],
        reward: npt.NDArray[np.float64],
        terminated: npt.NDArray[np.bool_],
        truncated: npt.NDArray[np.bool_],
        *,
        observe: bool = True,
        views: bool = True,
    ) -> None:
        """One step of a Gymnasium task (``task``: ``"heading-altitude"`` or
        ``"climb"``) for every aircraft, the engine of :mod:`afit_fdm.gym`
        (whose docstring defines the numbers), in one call with the GIL
        released: ``actions`` (``n`` times 4 for Palmer, 5 for Bourg; float32
        or float64 used in place, anything else converted to float64) clipped
        to -1..1 and set as the controls (in parallel over the fleet with
        ``parallel=True``; a NaN action raises ``ValueError`` naming the
        control it sets, before anything changes), ``frames`` frames flown, ``steps`` (int64,
        ``(n,)``) counted up by one, and with ``observe`` the state views
        refreshed and ``obs`` (float32, ``(n, 10)`` Palmer or ``(n, 11)``
        Bourg), ``reward`` (float64), ``terminated`` (not airborne) and
        ``truncated`` (``steps >= max_steps`` and not terminated) filled
        (bool, ``(n,)``). With ``observe`` but not ``views``, the state
        columns (:attr:`state`, ``fleet[name]``, :attr:`columns`) are left
        as they were and :attr:`status` is refreshed: for a caller that
        reads only the task's outputs and the statuses (the vector
        environment), which then skips writing every aircraft's state
        fields (and computing Bourg's speed and Euler angles) on each step;
        the next :meth:`step`, :meth:`reset`, :meth:`task_observe` or
        ``task_step`` with ``views`` refreshes them. The outputs are the
        same bits either way. Arrays of another dtype or shape raise
        ``TypeError``/``ValueError`` naming them.

        A step of many ``frames`` is stopped by Ctrl-C as :meth:`step` is:
        past the first chunk of frames (about 2,000,000 aircraft-frames,
        flown with the actions set), the rest flies in chunks with a look at
        the signals between two; ``KeyboardInterrupt`` is raised after the
        outputs (with ``observe``) are filled for the frames flown so far,
        which stay flown, and ``steps`` is counted up. Cut or not, the
        frames and outputs are the same bits."""
    def task_observe(
        self,
        task: str,
        target_alt_ft: npt.NDArray[np.float64],
        target_heading_deg: npt.NDArray[np.float64],
        steps: npt.NDArray[np.int64],
        max_steps: int,
        obs: npt.NDArray[np.float32],
        reward: npt.NDArray[np.float64],
        terminated: npt.NDArray[np.bool_],
        truncated: npt.NDArray[np.bool_],
    ) -> None:
        """The outputs of :meth:`task_step` for the fleet as it is (after a
        reset), without acting or flying."""

# --- Monte Carlo studies (the Python API is afit_fdm.study: Study, RunTable) ---

STATUS_CODES: List[str]
"""How a study's run ended, by ``status_code``: ``on_ground``, ``airborne``,
``landed_safe``, ``landed_rough``, ``crashed``, ``diverged``, ``start_refused``."""

@final
class _Study:
    """A parsed, validated study file (use :class:`afit_fdm.Study`)."""

    @staticmethod
    def from_toml(text: str, *, runs: Optional[int] = None, seed: Optional[int] = None) -> "_Study":
        """Parses a study file's text; ``ValueError`` names the line and key at fault."""
    @staticmethod
    def from_path(path: str, *, runs: Optional[int] = None, seed: Optional[int] = None) -> "_Study":
        """Reads and parses a study file: a regular file or a pipe of at most
        16 MiB (``OSError`` when it cannot be read or is neither, as
        ``/dev/zero``; ``ValueError`` past the limit)."""
    @property
    def text(self) -> str: ...
    @property
    def runs(self) -> int: ...
    @property
    def seed(self) -> int: ...
    @property
    def model(self) -> str: ...
    @property
    def measure_names(self) -> List[str]: ...
    @property
    def input_names(self) -> List[str]:
        """The drawn inputs' columns: ``input.`` and each dispersion's key, in the file's order."""
    def fly_columns(
        self, first: int, end: int, *, threads: Optional[int] = None, precision: str = "exact"
    ) -> Dict[str, Any]:
        """Flies runs ``first..end`` with the GIL released: ``run`` (uint64),
        ``status_code`` (uint8), ``frames`` (uint64), ``measures``: a list of
        ``(name, values float64, applies bool)`` (values 0.0 where not applicable),
        ``inputs``: a list of ``(name, values float64)`` (the values each run
        drew), ``fingerprint`` (uint64, the final state's; 0 where there is
        none) and ``has_fingerprint`` (bool; false for a refused start).
        Every 20 ms the calling thread looks at Python's pending signals; a
        signal whose handler raises (Ctrl-C's ``KeyboardInterrupt``) stops the
        fly and is raised from here (the runs flown so far are dropped)."""

def _math_atan2(y: npt.NDArray[np.float64], x: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """``fdm_core::math::atan2`` (fdlibm's, pure Rust: the same bits on every
    machine) of each pair, as a new array: the function of the Gymnasium
    tasks' track, for the tests' NumPy oracle."""

def _math_hypot(x: npt.NDArray[np.float64], y: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """``fdm_core::math::hypot`` (musl's, pure Rust) of each pair, as a new
    array: the function of the Gymnasium tasks' horizontal speed."""

def summarize_columns(
    run: npt.NDArray[np.uint64],
    status_code: npt.NDArray[np.uint8],
    frames: npt.NDArray[np.uint64],
    measures: Sequence[Tuple[str, npt.NDArray[np.float64], npt.NDArray[np.bool_]]],
    *,
    seed: int,
) -> str:
    """The summary of these columns as ``summary.json``'s text."""
