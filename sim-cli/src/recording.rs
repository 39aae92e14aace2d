//! `--record FILE`: the recording format (docs/recording.md), its reader and
//! writer live in the run library ([`fdm_run::recording`], re-exported here).
//! The writer is an [`fdm_run::Output`]: [`crate::flight::run_model`]
//! attaches it to the flight's run, which hands it every frame's actions and
//! every reset, so the headless and interactive loops record without knowing
//! it.

pub use fdm_run::recording::*;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Start;
    use crate::csv::CsvWriter;
    use crate::flight::ModelFlight;
    use crate::keys::{AppCommand, Input};
    use crate::models::CliModel;
    use crate::progress::StderrProgress;
    use crate::replay::replay_flight;
    use crate::report::Report;
    use crate::run::Flight;
    use crate::run::{run_headless, Flow, Session};
    use fdm_core::bourg::Bourg;
    use fdm_core::geodesy::GeodeticOrigin;
    use fdm_core::model::Model;
    use fdm_core::palmer::{Palmer, PalmerControls};
    use fdm_core::script::Script;
    use fdm_core::script::ScriptAction;
    use proptest::prelude::*;

    const PALMER_SCRIPT: &str = "1-20 throttle-up\n1-5 alpha-up\n300-310 bank-right\n\
                                 400-410 bank-left\n500-501 flaps-down\n";
    const BOURG_SCRIPT: &str = "1-5 thrust-up\n6-246 pitch-up\n247-307 roll-right\n\
                                400-420 yaw-left\n430-431 flaps-down\n";

    fn origin() -> GeodeticOrigin {
        "37.6,-122.4,4".parse().unwrap()
    }

    /// A flight of `start` at `fps` from [`origin`] flying `script`, no
    /// network output.
    fn flight<M: CliModel>(
        start: Start<M>,
        fps: u32,
        origin: GeodeticOrigin,
        script: Script<M::Action>,
    ) -> ModelFlight<M> {
        let scenario = fdm_run::Scenario {
            start,
            origin,
            fps,
            frames: 0,
            script,
        };
        ModelFlight::new(scenario, &fdm_run::links::LinkSettings::default()).unwrap()
    }

    /// The flight's CSV (`--csv`), attached to its run.
    type Csv<M> = fdm_run::SharedOutput<
        fdm_run::csv::CsvOutput<Vec<u8>, fn(&fdm_run::Frame<'_, M>) -> fdm_run::csv::FlightRow<M>>,
    >;

    fn attach_csv<M: CliModel>(flight: &mut ModelFlight<M>) -> Csv<M> {
        let csv = fdm_run::SharedOutput::new(fdm_run::csv::CsvOutput::new(
            CsvWriter::new(Vec::new(), "csv"),
            fdm_run::csv::FlightRow::<M>::of as fn(&fdm_run::Frame<'_, M>) -> _,
        ));
        flight.attach(csv.clone()).unwrap();
        csv
    }

    /// The CSV's bytes, after `flight.finish()`.
    fn csv_bytes<M: CliModel>(csv: &Csv<M>) -> Vec<u8> {
        csv.take().unwrap().into_inner().finish().unwrap()
    }

    fn quiet(frames: u64) -> StderrProgress {
        StderrProgress::with_enabled(frames, false)
    }

    /// What a flight produced: the JSON report, the CSV, and the recording.
    struct Outcome {
        json: String,
        csv: Vec<u8>,
        recording: Vec<u8>,
    }

    /// A headless flight of `frames` frames with `script`, recorded.
    fn headless<M: CliModel>(start: Start<M>, fps: u32, script: &str, frames: u64) -> Outcome {
        let writer = RecordWriter::new(Vec::new(), fps, &origin(), &start).unwrap();
        let script = Script::parse(script).unwrap();
        let mut flight = flight(start, fps, origin(), script);
        let recorder = fdm_run::SharedOutput::new(writer);
        flight.attach(recorder.clone()).unwrap();
        let csv = attach_csv(&mut flight);
        let report = run_headless(&mut flight, fps, frames, false, &mut quiet(frames)).unwrap();
        flight.finish().unwrap();
        Outcome {
            json: report.to_json().unwrap(),
            csv: csv_bytes(&csv),
            recording: recorder.take().unwrap().into_inner(),
        }
    }

    /// An interactive-style flight: `frames` frames of the interactive
    /// [`Session`] with synthetic key presses (every action of the model,
    /// pauses and resets, from a fixed pseudo-random sequence) on top of
    /// `script`, recorded. The report is what a headless run of the same
    /// frames would print.
    fn interactive<M: CliModel>(start: Start<M>, fps: u32, script: &str, frames: u64) -> Outcome {
        let writer = RecordWriter::new(Vec::new(), fps, &origin(), &start).unwrap();
        let script = Script::parse(script).unwrap();
        let mut flight = flight(start, fps, origin(), script);
        let recorder = fdm_run::SharedOutput::new(writer);
        flight.attach(recorder.clone()).unwrap();
        let csv = attach_csv(&mut flight);
        let mut session = Session::new();
        let actions = <M::Action as ScriptAction>::ALL;
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut resets = 0;
        for frame in 0..frames {
            if frame == frames / 2 {
                session
                    .handle(Input::App(AppCommand::Reset), &mut flight)
                    .unwrap();
                resets += 1;
            }
            // xorshift64: a fixed, model-independent key sequence.
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let keys = seed % 4;
            for k in 0..keys {
                let pick = (seed >> (8 + 8 * k)) % 200;
                let input = match pick {
                    0 => Input::App(AppCommand::Reset),
                    1 | 2 => Input::App(AppCommand::Pause),
                    n => Input::Action(actions[n as usize % actions.len()]),
                };
                resets += u32::from(input == Input::App(AppCommand::Reset));
                let flow = session.handle(input, &mut flight).unwrap();
                assert_eq!(flow, Flow::Continue);
            }
            session.advance(&mut flight).unwrap();
        }
        assert!(resets > 0, "the key sequence should reset at least once");
        flight.finish().unwrap();
        let report = Report::new(fps, session.total_frames(), &flight.snapshot());
        Outcome {
            json: report.to_json().unwrap(),
            csv: csv_bytes(&csv),
            recording: recorder.take().unwrap().into_inner(),
        }
    }

    /// Replays `bytes` as `sim-cli replay --json --csv` does.
    fn replay<M: CliModel>(bytes: &[u8]) -> (String, Vec<u8>) {
        replay_parsed(&Recording::<M>::parse(bytes).unwrap())
    }

    /// Replays a parsed (or salvaged) recording as `sim-cli replay --json
    /// --csv` does.
    fn replay_parsed<M: CliModel>(recording: &Recording<'_, M>) -> (String, Vec<u8>) {
        let mut flight = flight(
            recording.start.clone(),
            recording.fps,
            recording.origin,
            Script::default(),
        );
        let csv = attach_csv(&mut flight);
        let report = replay_flight(
            &mut flight,
            recording.events(),
            recording.fps,
            recording.frames,
            false,
            &mut quiet(recording.frames),
        )
        .unwrap();
        flight.finish().unwrap();
        (report.to_json().unwrap(), csv_bytes(&csv))
    }

    fn palmer_start() -> Start<Palmer> {
        Start {
            controls: PalmerControls {
                throttle: 0.5,
                alpha_deg: 2.0,
                ..PalmerControls::default()
            },
            ..Start::thesis()
        }
    }

    /// Bit-identical: the JSON prints every f64 in its shortest round-trip
    /// form (so equal text is equal bits) and the CSV likewise; tolerance 0.
    #[test]
    fn scripted_flights_replay_to_the_same_json_and_csv() {
        let p = headless(palmer_start(), 30, PALMER_SCRIPT, 1800);
        assert_eq!(replay::<Palmer>(&p.recording), (p.json, p.csv));
        let b = headless(Start::<Bourg>::thesis(), 30, BOURG_SCRIPT, 900);
        assert_eq!(replay::<Bourg>(&b.recording), (b.json, b.csv));
    }

    #[test]
    fn interactive_flights_with_pauses_and_resets_replay_to_the_same_json_and_csv() {
        let p = interactive(palmer_start(), 30, PALMER_SCRIPT, 2000);
        let info = parse_recording(&p.recording).unwrap();
        assert!(info.resets > 0 && info.frames > 0, "{info:?}");
        assert_eq!(replay::<Palmer>(&p.recording), (p.json, p.csv));
        let b = interactive(Start::<Bourg>::thesis(), 60, BOURG_SCRIPT, 2000);
        assert!(parse_recording(&b.recording).unwrap().resets > 0);
        assert_eq!(replay::<Bourg>(&b.recording), (b.json, b.csv));
    }

    #[test]
    fn the_header_carries_fps_origin_and_start() {
        let p = headless(palmer_start(), 25, "", 10);
        let r = Recording::<Palmer>::parse(&p.recording).unwrap();
        assert_eq!((r.fps, r.origin, r.frames, r.resets), (25, origin(), 10, 0));
        assert_eq!(r.start.controls, palmer_start().controls);
        assert_eq!(r.start.state, palmer_start().state);
        assert_eq!(r.start.aircraft, palmer_start().aircraft);
        let b = headless(Start::<Bourg>::thesis(), 30, "", 1);
        let r = Recording::<Bourg>::parse(&b.recording).unwrap();
        assert_eq!(r.start.aircraft, Bourg::default_aircraft());
        assert_eq!(r.start.state, Bourg::initial_state());
    }

    /// Identical frames are stored once within a block (a second of
    /// flight): an idle flight is one event per second, a scripted one an
    /// event per change of the frame's actions plus one per block a run
    /// spans.
    #[test]
    fn runs_of_identical_frames_are_one_event_per_block() {
        let idle = headless(palmer_start(), 30, "", 100_000);
        let info = parse_recording(&idle.recording).unwrap();
        assert_eq!(
            (info.events, info.frames),
            (100_000_u64.div_ceil(30), 100_000)
        );
        let short = headless(palmer_start(), 30, "", 1);
        // Per second of idle flight: a block's length and checksum (12 bytes)
        // and one event of 3 bytes (tag, count 30, no actions).
        let per_second = (idle.recording.len() - short.recording.len()) as f64 / (100_000.0 / 30.0);
        assert!(
            (14.9..=15.1).contains(&per_second),
            "{per_second} bytes per second"
        );
        let scripted = headless(palmer_start(), 30, PALMER_SCRIPT, 1800);
        // The script's runs of identical frames: 1-5 (2 actions), 6-20,
        // 21-299 idle, 300-310, idle, 400-410, idle, 500-501, idle; each is
        // one event in every block (frames 1-30, 31-60, ...) it touches.
        let runs = [
            (1, 5),
            (6, 20),
            (21, 299),
            (300, 310),
            (311, 399),
            (400, 410),
            (411, 499),
            (500, 501),
            (502, 1800),
        ];
        let block = |frame: u64| (frame - 1) / 30;
        let expected: u64 = runs.iter().map(|&(a, b)| block(b) - block(a) + 1).sum();
        assert_eq!(
            parse_recording(&scripted.recording).unwrap().events,
            expected
        );
    }

    /// The writer and the reader agree on what a recording may hold: a frame
    /// applying 1.3 million actions (a script of as many rules acting on
    /// frame 1; more than 1 MiB in one event) records and replays.
    #[test]
    fn a_frame_of_a_million_actions_records_and_replays() {
        let start = palmer_start();
        let mut writer =
            RecordWriter::<_, Vec<u8>>::new(Vec::new(), 30, &origin(), &start).unwrap();
        let actions = vec![fdm_core::palmer::PalmerAction::ThrottleUp; 1_300_000];
        writer.frame(&actions).unwrap();
        writer.frame(&[]).unwrap();
        writer.finish().unwrap();
        let bytes = writer.into_inner();
        assert!(bytes.len() > 1 << 20, "{} bytes", bytes.len());
        let recording = Recording::<Palmer>::parse(&bytes).unwrap();
        assert_eq!(recording.frames, 2);
        let first = recording.events().next().unwrap().unwrap();
        assert_eq!(first, Replayed::Frames { count: 1, actions });
    }

    /// An interactive-style Palmer recording with resets (made once).
    fn sample() -> Vec<u8> {
        static SAMPLE: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
        SAMPLE
            .get_or_init(|| interactive(palmer_start(), 30, PALMER_SCRIPT, 300).recording)
            .clone()
    }

    #[test]
    fn every_truncation_is_refused() {
        let bytes = sample();
        for len in 0..bytes.len() {
            let err = parse_recording(&bytes[..len]).unwrap_err();
            assert!(matches!(err, RecordingError::Truncated(_)), "{len}: {err}");
        }
    }

    /// A recording cut anywhere (a killed flight, a lost machine) replays
    /// every frame of its intact blocks, and those frames are exactly the
    /// flight's: the salvaged replay's CSV is the complete replay's CSV up
    /// to the cut (tolerance 0: equal text is equal bits). A cut inside the
    /// header leaves nothing to replay and is refused as truncated; zeros
    /// where the tail should be (written by a file system after a power
    /// loss) are a cut too.
    #[test]
    fn every_cut_replays_the_frames_before_it() {
        let bytes = sample();
        let complete = Recording::<Palmer>::parse(&bytes).unwrap();
        let (_, full_csv) = replay::<Palmer>(&bytes);
        let full_csv = String::from_utf8(full_csv).unwrap();
        let mut seen = std::collections::BTreeMap::new();
        let mut last_frames = 0;
        for len in 0..bytes.len() {
            let cut_bytes = &bytes[..len];
            let Ok((recording, cut)) = Recording::<Palmer>::parse_salvaging(cut_bytes) else {
                assert_eq!(last_frames, 0, "{len}: refused after a salvageable cut");
                continue;
            };
            let cut = cut.expect("a cut file has no end marker");
            assert_eq!(cut.frames, recording.frames);
            assert!(
                cut.frames >= last_frames,
                "{len}: fewer frames than a shorter cut"
            );
            assert!(cut.frames <= complete.frames);
            assert!(cut.at_byte <= len as u64);
            last_frames = cut.frames;
            let mut zeroed = cut_bytes.to_vec();
            zeroed.resize(bytes.len(), 0);
            let (_, zero_cut) = Recording::<Palmer>::parse_salvaging(&zeroed).unwrap();
            assert_eq!(zero_cut, Some(cut), "{len}: zeros after the cut");
            seen.entry(cut.frames).or_insert(len);
        }
        assert!(seen.len() > 5, "the sample spans several blocks: {seen:?}");
        for (&frames, &len) in &seen {
            let recording = Recording::<Palmer>::parse_salvaging(&bytes[..len])
                .unwrap()
                .0;
            let csv = String::from_utf8(replay_parsed(&recording).1).unwrap();
            assert!(
                full_csv.starts_with(&csv),
                "{frames} frames salvaged from {len} bytes: not a prefix of the full replay"
            );
            // The model line, the header line and frame 0, then a row per
            // frame and one more per reset (a reset writes a new frame 0).
            assert!(
                csv.starts_with("# model: palmer\nframe,time_s,"),
                "{csv:.80}"
            );
            let resets = recording.resets as usize;
            assert_eq!(csv.lines().count(), 3 + frames as usize + resets);
        }
    }

    /// FNV-1a detects any single-byte change before the end marker, and the
    /// marker's own bytes are checked against the events: every one-byte
    /// change anywhere is refused.
    #[test]
    fn every_single_byte_change_is_refused() {
        let bytes = sample();
        for i in 0..bytes.len() {
            for mask in [0x01, 0x80, 0xff] {
                let mut bad = bytes.clone();
                bad[i] ^= mask;
                assert!(parse_recording(&bad).is_err(), "byte {i} ^ {mask:#x}");
            }
        }
    }

    #[test]
    fn wrong_version_model_magic_and_trailing_bytes_are_named() {
        let bytes = sample();
        let mut v4 = bytes.clone();
        v4[8] = 4;
        assert_eq!(
            parse_recording(&v4).unwrap_err().to_string(),
            "recording format version 4; this sim-cli reads versions 1, 2 and 3"
        );
        assert_eq!(
            Recording::<Bourg>::parse(&bytes).unwrap_err(),
            RecordingError::WrongModel {
                expected: "bourg",
                found: "palmer".to_owned()
            }
        );
        // A model name this sim-cli does not know (same length as "palmer").
        let mut glider = bytes.clone();
        let at = bytes.windows(6).position(|w| w == b"palmer").unwrap();
        glider[at..at + 6].copy_from_slice(b"glider");
        assert_eq!(
            parse_recording(&glider).unwrap_err(),
            RecordingError::UnknownModel("glider".to_owned())
        );
        // Control characters in a stored name are escaped in the message.
        let mut bell = bytes.clone();
        bell[at + 2] = 0x07;
        let message = parse_recording(&bell).unwrap_err().to_string();
        assert!(message.contains("`pa\\u{7}mer`"), "{message}");
        let mut magic = bytes.clone();
        magic[0] = b'X';
        assert_eq!(parse_recording(&magic), Err(RecordingError::NotARecording));
        let mut trailing = bytes.clone();
        trailing.push(0);
        assert!(parse_recording(&trailing)
            .unwrap_err()
            .to_string()
            .contains("1 bytes after the end marker"));
        assert!(parse_recording(&bytes).is_ok());
    }

    #[test]
    fn lengths_beyond_the_limits_are_refused_without_allocating() {
        // A header whose model name claims 2^60 bytes.
        let mut huge = MAGIC.to_vec();
        huge.extend(FORMAT_VERSION.to_le_bytes());
        huge.push(253); // varint tag: u64 follows
        huge.extend((1_u64 << 60).to_le_bytes());
        assert!(matches!(
            parse_recording(&huge),
            Err(RecordingError::Corrupt(_) | RecordingError::Truncated(_))
        ));
        let too_big = vec![0_u8; usize::try_from(MAX_RECORDING_BYTES).unwrap() + 1];
        assert!(matches!(
            parse_recording(&too_big),
            Err(RecordingError::TooLarge { .. })
        ));
    }

    #[test]
    fn an_unfinished_recording_is_truncated() {
        let start = palmer_start();
        let mut writer =
            RecordWriter::<_, Vec<u8>>::new(Vec::new(), 30, &origin(), &start).unwrap();
        writer.frame(&[]).unwrap();
        writer.reset().unwrap();
        let bytes = writer.into_inner();
        assert_eq!(
            parse_recording(&bytes),
            Err(RecordingError::Truncated("before its end marker"))
        );
        // Nothing reached a block yet (it closes after a second of flight).
        let (recording, cut) = Recording::<Palmer>::parse_salvaging(&bytes).unwrap();
        assert_eq!(recording.frames, 0);
        assert_eq!(cut.map(|c| c.frames), Some(0));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        /// Mangled recordings (cut, bytes overwritten, inserted or removed)
        /// never panic the parser, and a mangled file that still parses is
        /// the original (nothing else gets past the checksum).
        #[test]
        fn mangled_recordings_never_panic(
            cut in any::<prop::sample::Index>(),
            edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>(), 0..3_u8), 0..6),
        ) {
            let original = sample();
            let mut bytes = original.clone();
            for (at, byte, kind) in edits {
                if bytes.is_empty() {
                    break;
                }
                let i = at.index(bytes.len());
                match kind {
                    0 => bytes[i] = byte,
                    1 => bytes.insert(i, byte),
                    _ => { bytes.remove(i); }
                }
            }
            let keep = cut.index(bytes.len() + 1);
            if keep < bytes.len() && keep % 2 == 0 {
                bytes.truncate(keep);
            }
            if let Ok(info) = parse_recording(&bytes) {
                prop_assert_eq!(&bytes, &original);
                prop_assert_eq!(info.model, "palmer");
            }
        }

        /// Arbitrary bytes after a valid prefix never panic either.
        #[test]
        fn arbitrary_bodies_never_panic(body in prop::collection::vec(any::<u8>(), 0..512)) {
            let mut bytes = MAGIC.to_vec();
            bytes.extend(FORMAT_VERSION.to_le_bytes());
            bytes.extend(&body);
            let _ = parse_recording(&bytes);
            let mut bytes = sample();
            let header_end = bytes.len().saturating_sub(20);
            bytes.truncate(header_end);
            bytes.extend(&body);
            let _ = parse_recording(&bytes);
        }
    }
}
