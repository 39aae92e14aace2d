//! `sim-cli fleet`: many aircraft of one model flown headless by the run
//! library's fleet runs ([`fdm_run::fleet`]), to measure how many this
//! machine can fly: the flags become a [`FleetScenario`], spawning shows a
//! progress bar on a terminal, a signal stops the run between frames, and
//! the [`FleetReport`] is printed as its summary ([`FleetReport::summary`])
//! or (`--json`) one JSON object.
//!
//! With `--dis` every aircraft is also published as a DIS entity after every
//! frame (its time reported apart, in `dis.publish_seconds`), `--acmi` writes
//! every aircraft's track, and `--realtime` paces the frames at 1/30 s of
//! wall-clock time. `--fg-mp` streams the fleet to FlightGear instead
//! ([`crate::fleet_mp`]).

use anyhow::Context as _;
use fdm_run::acmi::AcmiError;
use fdm_run::fleet::Kernel;
use fdm_run::fleet::{FleetDisConfig, FleetError, FleetReport, FleetRun, FleetScenario};

use crate::args::{FleetArgs, FleetKernel};
use crate::error::CliError;
use crate::models::{CliModel, WithModel};
use crate::progress::StderrProgress;

/// The frame rate the fleet flies at and the one "could fly" refers to.
pub use crate::args::FLEET_FPS;

impl From<FleetError> for CliError {
    /// A fleet run's error in the command line's words: what the flags asked
    /// for that cannot be flown, or a fleet too large, is a usage error (exit
    /// 2); the rest happened while flying (exit 1).
    fn from(error: FleetError) -> Self {
        match error {
            FleetError::EcsNeedsExact => CliError::usage(
                "--precision fast needs --kernel lanes \
                 (--kernel ecs flies every aircraft with the model's own exact step)",
            ),
            FleetError::LanesNeedDemonstration => CliError::usage(
                "--altitude-ft, --speed-kt, --heading-deg and --trim need --kernel ecs \
                 (the lanes kernel flies the demonstration fleet only)",
            ),
            FleetError::Precision(e) => CliError::usage(format!("--precision: {e}")),
            FleetError::TooMany(_) | FleetError::Memory(_) => CliError::usage(error),
            FleetError::Start(refused) => crate::start::refused(refused),
            FleetError::Dis(e) => e.into(),
            // The only output sim-cli attaches to a fleet is its --acmi file.
            FleetError::Output(e) => match e.downcast::<AcmiError>() {
                Ok(e) => anyhow::Error::from(*e),
                Err(e) => anyhow::anyhow!(e),
            }
            .context("--acmi")
            .into(),
            FleetError::ThreadPool(e) => anyhow::Error::from(e)
                .context("building the thread pool")
                .into(),
            FleetError::Multiplayer(e) => anyhow::Error::from(e).into(),
            e => CliError::runtime(e),
        }
    }
}

/// [`measure`] for the model the arguments name.
struct Measure<'a>(&'a FleetArgs);

impl WithModel for Measure<'_> {
    type Output = Result<FleetReport, CliError>;

    fn call<M: CliModel>(self) -> Self::Output {
        let args = self.0;
        let mut scenario = FleetScenario::new(args.aircraft, args.frames);
        scenario.threads = args.threads;
        scenario.kernel = match args.kernel {
            FleetKernel::Lanes => Kernel::Lanes,
            FleetKernel::Ecs => Kernel::Ecs,
        };
        scenario.precision = args.precision.into();
        scenario.start = args.start.options();
        scenario.realtime = args.show.realtime;
        // The ECS kernel's precision is refused before the DIS target is resolved.
        if scenario.kernel == Kernel::Ecs {
            scenario.check_kernel::<M>()?;
        }
        scenario.dis = args.dis.common.settings()?.map(|settings| FleetDisConfig {
            settings,
            entity_base: args.dis.entity_base,
        });
        let mut bar: Option<StderrProgress> = None;
        let mut run = FleetRun::<M>::new(scenario, &mut |done, total| {
            bar.get_or_insert_with(|| StderrProgress::new(total))
                .tick(done);
        })?;
        drop(bar);
        // A named pipe first waits for its reader, saying so.
        let _reader = crate::input::await_pipe_readers(&[(args.acmi.acmi.as_deref(), "--acmi")])?;
        let acmi = crate::acmi::create(&args.acmi, M::NAME, FLEET_FPS, &run.origin(), &[])?;
        if let Some(acmi) = acmi {
            run.attach(acmi)?;
        }
        // A signal stops the run early (crate::signals; checked between
        // frames, or every second of flight); the first DIS failure is
        // written once on stderr, never fatal.
        run.run_to_end(
            || crate::signals::stop_requested().is_some(),
            |message| eprintln!("{}", crate::run::link_warning(message)),
        )?;
        run.finish()?;
        Ok(run.report())
    }
}

/// Flies the fleet and measures it.
///
/// # Errors
/// [`CliError::Usage`] for a fleet that cannot be flown as asked or does not
/// fit this machine's memory; [`CliError::Runtime`] if the thread pool cannot
/// be built or an output fails.
pub fn measure(args: &FleetArgs) -> Result<FleetReport, CliError> {
    args.model.with(Measure(args))
}

/// `sim-cli fleet`: [`measure`], then the summary or (`--json`) the report
/// as one JSON object on stdout (the summary on stderr when `--acmi` writes
/// the standard output, [`crate::config::summary_on_stderr`]).
///
/// # Errors
/// See [`measure`]; writing to stdout can fail too (exit status 1).
pub fn run(args: &FleetArgs) -> Result<(), CliError> {
    if args.show.fg_mp.is_some() && args.acmi.acmi.is_some() {
        return Err(CliError::usage(
            "--acmi cannot be combined with --fg-mp (fly the fleet without --fg-mp to write it)",
        ));
    }
    if let Some(text) = crate::fleet_mp::run_show(args)? {
        return crate::print_line(&text);
    }
    let summary_on_stderr = crate::config::summary_on_stderr(
        &[(args.acmi.acmi.as_deref(), "--acmi")],
        args.json,
        false,
    )?;
    let report = measure(args)?;
    let text = if args.json {
        serde_json::to_string(&report).context("encoding the report")?
    } else {
        report.summary()
    };
    crate::print_report(&text, summary_on_stderr)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::args::{FleetPrecision, ModelKind};

    #[test]
    fn a_small_fleet_reports_consistent_numbers() {
        for (model, threads, kernel) in [
            (ModelKind::named("palmer").unwrap(), 2, FleetKernel::Ecs),
            (ModelKind::named("bourg").unwrap(), 1, FleetKernel::Ecs),
            (ModelKind::named("palmer").unwrap(), 2, FleetKernel::Lanes),
            (ModelKind::named("bourg").unwrap(), 1, FleetKernel::Lanes),
        ] {
            let args = FleetArgs {
                model,
                aircraft: 10,
                frames: 3,
                threads: Some(threads),
                kernel,
                precision: FleetPrecision::Exact,
                json: true,
                start: crate::start::StartArgs::default(),
                dis: crate::dis::FleetDisArgs::default(),
                show: crate::args::FleetShowArgs::default(),
                acmi: crate::args::AcmiArgs::default(),
            };
            let report = measure(&args).unwrap();
            assert_eq!(report.model, model.name());
            assert_eq!((report.aircraft, report.frames), (10, 3));
            assert_eq!(report.threads, threads);
            assert!(report.seconds > 0.0);
            let rate = 30.0 / report.seconds;
            assert!((report.aircraft_steps_per_s - rate).abs() <= 1e-9 * rate);
            assert_eq!(
                report.aircraft_at_30hz,
                (report.aircraft_steps_per_s / 30.0).floor() as u64
            );
            assert!(report.summary().contains("aircraft at 30 Hz"));
            assert_eq!(report.statuses.airborne, 10, "{:?}", report.statuses);
            assert_eq!(report.diverged, 0);
        }
    }

    /// The run library's refusals keep their exit statuses: a fleet too
    /// large for memory is a usage error (2).
    #[test]
    fn fleets_that_do_not_fit_are_usage_errors() {
        use fdm_core::model::Model;
        use fdm_core::palmer::Palmer;
        use fdm_run::memory;
        let per = memory::estimated_bytes_per_aircraft::<Palmer>();
        let refused = memory::check_fleet(Palmer::NAME, 10_000_000, per, Some(1 << 30));
        let err = CliError::from(FleetError::from(refused.unwrap_err()));
        assert_eq!(err.exit_code(), 2);
        assert!(err
            .to_string()
            .starts_with("a fleet of 10000000 palmer aircraft needs about "));
        assert_eq!(CliError::from(FleetError::EcsNeedsExact).exit_code(), 2);
    }
}
