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
