//! The `LaneFleet` trait's methods, called through the trait (as `fdm-run`,
//! `sim-cli` and the Python package call them) on both models' fleets,
//! against their documentation.

use fdm_core::bourg::Bourg;
use fdm_core::palmer::Palmer;
use fdm_fleet::{Fleet, FleetKernel, LaneFleet};

/// `len` counts the aircraft and `is_empty` is `len() == 0`: a fleet made
/// from no starts is empty, one aircraft makes it not empty.
#[test]
fn is_empty_means_no_aircraft() {
    fn check<M: FleetKernel>() {
        let empty = <Fleet<M> as LaneFleet>::from_starts(M::default_aircraft(), []).unwrap();
        assert_eq!(LaneFleet::len(&empty), 0, "{}", M::NAME);
        assert!(LaneFleet::is_empty(&empty), "{}", M::NAME);
        let one = <Fleet<M> as LaneFleet>::from_starts(
            M::default_aircraft(),
            [(M::initial_controls(), M::initial_state())],
        )
        .unwrap();
        assert_eq!(LaneFleet::len(&one), 1, "{}", M::NAME);
        assert!(!LaneFleet::is_empty(&one), "{}", M::NAME);
        let demonstration = <Fleet<M> as LaneFleet>::demonstration(21).unwrap();
        assert_eq!(LaneFleet::len(&demonstration), 21, "{}", M::NAME);
        assert!(!LaneFleet::is_empty(&demonstration), "{}", M::NAME);
    }
    check::<Palmer>();
    check::<Bourg>();
}

/// Every aircraft's state, controls and status read through the trait are
/// the fleet's (the starts it was made from, the initial status for their
/// height); the aircraft is the one given; out of range is `None`.
#[test]
fn reads_through_the_trait_are_the_fleets() {
    fn check<M: FleetKernel>()
    where
        M::State: PartialEq + std::fmt::Debug,
        M::Controls: PartialEq + std::fmt::Debug,
        M::Aircraft: PartialEq + std::fmt::Debug,
    {
        let n = 11;
        let fleet = <Fleet<M> as LaneFleet>::demonstration(n).unwrap();
        assert_eq!(LaneFleet::aircraft(&fleet), &M::default_aircraft());
        for i in 0..n {
            let (controls, state) = M::fleet_member(i);
            assert_eq!(LaneFleet::state(&fleet, i), Some(state), "{} {i}", M::NAME);
            assert_eq!(
                LaneFleet::controls(&fleet, i),
                Some(controls),
                "{} {i}",
                M::NAME
            );
            assert_eq!(
                LaneFleet::status(&fleet, i),
                Some(fdm_core::model::FlightStatus::initial(
                    M::view(&M::default_aircraft(), &controls, &state)
                        .position_m
                        .z
                )),
                "{} {i}",
                M::NAME
            );
        }
        assert_eq!(LaneFleet::state(&fleet, n), None);
        assert_eq!(LaneFleet::controls(&fleet, n), None);
        assert_eq!(LaneFleet::status(&fleet, n), None);
    }
    check::<Palmer>();
    check::<Bourg>();
}

/// `positions_m` replaces `out` with every aircraft's view position, metres,
/// in index order, bit for bit.
#[test]
fn positions_are_the_views_positions() {
    fn check<M: FleetKernel>() {
        let mut fleet = <Fleet<M> as LaneFleet>::demonstration(13).unwrap();
        LaneFleet::par_fly(&mut fleet, 30.0, fdm_fleet::Precision::Exact).unwrap();
        let mut out = vec![nalgebra::Vector3::new(1.0, 2.0, 3.0); 40];
        LaneFleet::positions_m(&fleet, &mut out);
        assert_eq!(out.len(), 13, "{}", M::NAME);
        for (i, p) in out.iter().enumerate() {
            let s = LaneFleet::state(&fleet, i).unwrap();
            let c = LaneFleet::controls(&fleet, i).unwrap();
            let view = M::view(&M::default_aircraft(), &c, &s);
            assert_eq!(
                p.map(f64::to_bits),
                view.position_m.map(f64::to_bits),
                "{} {i}",
                M::NAME
            );
        }
    }
    check::<Palmer>();
    check::<Bourg>();
}

/// `check_precision`: `Exact` for every model, `Fast` only for a model with a
/// fast kernel (Palmer's), the refusal naming the model.
#[test]
fn precision_is_checked_per_model() {
    use fdm_fleet::{FleetError, Precision};
    assert_eq!(
        <Fleet<Palmer> as LaneFleet>::check_precision(Precision::Exact),
        Ok(())
    );
    assert_eq!(
        <Fleet<Palmer> as LaneFleet>::check_precision(Precision::Fast),
        Ok(())
    );
    assert_eq!(
        <Fleet<Bourg> as LaneFleet>::check_precision(Precision::Exact),
        Ok(())
    );
    assert_eq!(
        <Fleet<Bourg> as LaneFleet>::check_precision(Precision::Fast),
        Err(FleetError::PrecisionUnavailable {
            model: <Bourg as fdm_core::model::Model>::NAME,
            precision: Precision::Fast
        })
    );
    let mut bourg = <Fleet<Bourg> as LaneFleet>::demonstration(3).unwrap();
    let before = LaneFleet::state(&bourg, 0);
    assert!(LaneFleet::par_step(&mut bourg, 30.0, Precision::Fast).is_err());
    assert!(LaneFleet::par_fly(&mut bourg, 30.0, Precision::Fast).is_err());
    assert_eq!(
        LaneFleet::state(&bourg, 0),
        before,
        "nothing flown on a refusal"
    );
}

/// `par_step` and `par_fly` at `fps` are the fleet's own step and frame at
/// the model's time step for that rate, bit for bit; a step leaves the
/// statuses alone, a frame does not step a crashed aircraft.
#[test]
fn par_step_and_par_fly_are_the_fleets_step_and_frame_at_the_rate() {
    fn check<M: FleetKernel>()
    where
        M::State: PartialEq + std::fmt::Debug,
    {
        use fdm_fleet::Precision;
        let fps = 60.0;
        let mut by_trait = <Fleet<M> as LaneFleet>::demonstration(19).unwrap();
        let mut direct = by_trait.clone();
        for _ in 0..5 {
            LaneFleet::par_step(&mut by_trait, fps, Precision::Exact).unwrap();
            direct
                .step_with(M::time_step(fps), Precision::Exact)
                .unwrap();
        }
        for _ in 0..5 {
            LaneFleet::par_fly(&mut by_trait, fps, Precision::Exact).unwrap();
            direct
                .fly_with(M::time_step(fps), Precision::Exact)
                .unwrap();
        }
        for i in 0..19 {
            assert_eq!(
                LaneFleet::state(&by_trait, i),
                direct.state(i),
                "{} {i}",
                M::NAME
            );
        }
        // One frame at 30 FPS is not one at 60: the rate is used.
        let mut at_30 = <Fleet<M> as LaneFleet>::demonstration(1).unwrap();
        let mut at_60 = at_30.clone();
        LaneFleet::par_step(&mut at_30, 30.0, Precision::Exact).unwrap();
        LaneFleet::par_step(&mut at_60, 60.0, Precision::Exact).unwrap();
        assert_ne!(LaneFleet::state(&at_30, 0), LaneFleet::state(&at_60, 0));
    }
    check::<Palmer>();
    check::<Bourg>();
}

/// `piece_aircraft` rounds the request up to whole blocks of the kernel's
/// lanes, at least one block.
#[test]
fn pieces_are_whole_blocks() {
    fn check<M: FleetKernel>() {
        let lanes = <M::Lanes as fdm_core::real::Real>::LANES;
        let piece = <Fleet<M> as LaneFleet>::piece_aircraft;
        assert_eq!(piece(0), lanes, "{}", M::NAME);
        assert_eq!(piece(1), lanes, "{}", M::NAME);
        assert_eq!(piece(lanes), lanes, "{}", M::NAME);
        assert_eq!(piece(lanes + 1), 2 * lanes, "{}", M::NAME);
        assert_eq!(
            piece(1024),
            1024_usize.div_ceil(lanes) * lanes,
            "{}",
            M::NAME
        );
    }
    check::<Palmer>();
    check::<Bourg>();
}

/// The instruction set and the bytes per aircraft through the trait are the
/// fleet's: the instruction set one of the three documented names, the
/// bytes per aircraft times a whole number of blocks' aircraft the fleet's
/// arrays.
#[test]
fn instruction_set_and_bytes_are_the_fleets() {
    fn check<M: FleetKernel>() {
        let lanes = <M::Lanes as fdm_core::real::Real>::LANES;
        let fleet = <Fleet<M> as LaneFleet>::demonstration(3 * lanes).unwrap();
        let set = LaneFleet::instruction_set(&fleet);
        assert_eq!(set, fleet.instruction_set(), "{}", M::NAME);
        assert!(
            ["x86-64-v4", "x86-64-v3", "baseline"].contains(&set),
            "{set}"
        );
        let per = <Fleet<M> as LaneFleet>::bytes_per_aircraft();
        assert_eq!(per, Fleet::<M>::bytes_per_aircraft(), "{}", M::NAME);
        assert!(per > 0);
        assert_eq!(per * 3 * lanes, fleet.bytes(), "{}", M::NAME);
    }
    check::<Palmer>();
    check::<Bourg>();
}

/// `par_update_controls` through the trait replaces aircraft `i`'s controls
/// with `f(i, current)`, as setting each one does.
#[test]
fn updated_controls_are_set_controls() {
    fn check<M: FleetKernel>()
    where
        M::Controls: PartialEq + std::fmt::Debug,
        M::State: PartialEq + std::fmt::Debug,
    {
        let n = 10;
        let mut by_trait = <Fleet<M> as LaneFleet>::demonstration(n).unwrap();
        let mut direct = by_trait.clone();
        let swap = |i: usize, c: M::Controls| {
            if i.is_multiple_of(3) {
                M::fleet_member(i + 1).0
            } else {
                c
            }
        };
        LaneFleet::par_update_controls(&mut by_trait, swap);
        for i in 0..n {
            direct
                .set_controls(i, swap(i, direct.controls(i).unwrap()))
                .unwrap();
        }
        LaneFleet::par_fly(&mut by_trait, 30.0, fdm_fleet::Precision::Exact).unwrap();
        LaneFleet::par_fly(&mut direct, 30.0, fdm_fleet::Precision::Exact).unwrap();
        for i in 0..n {
            assert_eq!(LaneFleet::controls(&by_trait, i), direct.controls(i), "{i}");
            assert_eq!(LaneFleet::state(&by_trait, i), direct.state(i), "{i}");
        }
    }
    check::<Palmer>();
    check::<Bourg>();
}

/// `FleetError`'s equality as documented: equal variants with equal fields,
/// two `InvalidAircraft` equal when their reasons read the same (two
/// allocations of the same message), and nothing equal across variants or
/// with any field changed.
#[test]
fn fleet_errors_are_equal_when_their_variant_and_fields_are() {
    use fdm_fleet::{FleetError, Precision};
    use std::sync::Arc;
    let invalid = |reason: &str| {
        FleetError::InvalidAircraft(Arc::new(std::io::Error::other(reason.to_owned())))
    };
    let errors = [
        invalid("wing area must be positive"),
        invalid("mass must be positive"),
        FleetError::OutOfRange { index: 3, len: 2 },
        FleetError::OutOfRange { index: 4, len: 2 },
        FleetError::OutOfRange { index: 3, len: 1 },
        FleetError::UnknownPrecision("quick".to_owned()),
        FleetError::UnknownPrecision("rough".to_owned()),
        FleetError::PrecisionUnavailable {
            model: "bourg",
            precision: Precision::Fast,
        },
        FleetError::PrecisionUnavailable {
            model: "palmer",
            precision: Precision::Fast,
        },
        FleetError::PrecisionUnavailable {
            model: "bourg",
            precision: Precision::Exact,
        },
    ];
    for (i, a) in errors.iter().enumerate() {
        for (j, b) in errors.iter().enumerate() {
            assert_eq!(a == b, i == j, "{a:?} == {b:?}");
        }
    }
    assert_eq!(
        invalid("wing area must be positive"),
        invalid("wing area must be positive")
    );
    assert_eq!(
        FleetError::UnknownPrecision("quick".to_owned()),
        FleetError::UnknownPrecision(String::from("quick"))
    );
}

/// `len` and `is_empty` count the aircraft pushed: none in a new fleet,
/// then one more per push (the index `push` returns).
#[test]
fn len_and_is_empty_count_the_aircraft() {
    use fdm_core::model::Model;
    let mut fleet = Fleet::<Palmer>::try_new(Palmer::default_aircraft()).unwrap();
    assert_eq!((fleet.len(), fleet.is_empty()), (0, true));
    for i in 0..9 {
        let (controls, state) = Palmer::fleet_member(i);
        assert_eq!(fleet.push(state, controls), i);
        assert_eq!((fleet.len(), fleet.is_empty()), (i + 1, false));
    }
}

/// The instruction set is the one pulp detects on this CPU (the fleet's
/// dispatcher), under the documented names: AVX-512 `"x86-64-v4"`, AVX2
/// and FMA `"x86-64-v3"`, anything else `"baseline"`.
#[test]
fn instruction_set_is_the_detected_one() {
    #[allow(unreachable_patterns)] // `Arch` is non-exhaustive; other targets
    let detected = match pulp::Arch::new() {
        #[cfg(target_arch = "x86_64")]
        pulp::Arch::V4(_) => "x86-64-v4",
        #[cfg(target_arch = "x86_64")]
        pulp::Arch::V3(_) => "x86-64-v3",
        _ => "baseline",
    };
    use fdm_core::model::Model;
    let fleet = Fleet::<Palmer>::try_new(Palmer::default_aircraft()).unwrap();
    assert_eq!(fleet.instruction_set(), detected);
    let fleet = Fleet::<Bourg>::try_new(Bourg::default_aircraft()).unwrap();
    assert_eq!(fleet.instruction_set(), detected);
}
