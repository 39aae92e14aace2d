//! A model's state and controls as named columns of numbers: what a program
//! that shows a model as plain numbers needs of it (the Python bindings'
//! `Flight.state`, `Fleet`'s NumPy columns and a replay's table, through
//! `afit-fdm-py`), so that such a program names no model.
//!
//! The state's columns are read-only; the controls' columns have ranges and
//! are set one at a time by their index ([`ColumnModel::with_control`]).
//! Units are in the columns' names. Each model implements [`ColumnModel`] in
//! its adapter module ([`super::palmer`], [`super::bourg`]).
//!
//! A program steps many aircraft's columns in its hot loop (the Gymnasium
//! vector environment writes every aircraft's columns each step), so the
//! implementations are `#[inline]` (they are called from other crates) and
//! the fields some models compute faster a block of aircraft at a time have
//! a lane-wise form ([`ColumnModel::block_fields`]).

use fdm_core::model::Model;

/// A control column's name and its accepted range (inclusive; a control
/// with a set of allowed values in that range, such as Palmer's flaps, also
/// checks the value in [`ColumnModel::with_control`]).
pub type ControlRange = (&'static str, f64, f64);

/// Most fields [`ColumnModel::block_fields`] computes.
pub const MAX_BLOCK_FIELDS: usize = 4;

/// A model's state and controls as named numbers, and its controls set by
/// index.
pub trait ColumnModel: Model {
    /// Names of [`state_values`](Self::state_values), units in the names.
    const STATE_FIELDS: &'static [&'static str];

    /// Names and ranges of [`control_values`](Self::control_values), units
    /// in the names.
    const CONTROL_FIELDS: &'static [ControlRange];

    /// Controls (of [`CONTROL_FIELDS`](Self::CONTROL_FIELDS)) that a trimmed
    /// start sets itself, so that they cannot be given with it, each with
    /// what the trim sets instead (for the error message: "the trim sets
    /// ...").
    const TRIM_SETS: &'static [(&'static str, &'static str)];

    /// The state as numbers, in [`STATE_FIELDS`](Self::STATE_FIELDS) order
    /// (`f32` values widened exactly; booleans 0 or 1).
    fn state_values(state: &Self::State, out: &mut [f64]);

    /// `out` becomes the controls as numbers, in
    /// [`CONTROL_FIELDS`](Self::CONTROL_FIELDS) order.
    fn control_values(controls: &Self::Controls, out: &mut [f64]);

    /// `controls` with control `index` (of
    /// [`CONTROL_FIELDS`](Self::CONTROL_FIELDS)) set to `value`, which the
    /// caller has checked is finite and in range.
    ///
    /// # Errors
    /// A message when the value is in range but not one of the allowed
    /// values (Palmer's flaps: 0, 20 or 40).
    fn with_control(
        controls: Self::Controls,
        index: usize,
        value: f64,
    ) -> Result<Self::Controls, String>;

    /// How many of the last [`STATE_FIELDS`](Self::STATE_FIELDS) (at most
    /// [`MAX_BLOCK_FIELDS`]) a program may compute a block of aircraft at a
    /// time ([`block_fields`](Self::block_fields): Bourg's speed and three
    /// Euler angles); the others come from
    /// [`state_values_head`](Self::state_values_head).
    const BLOCK_FIELDS: usize = 0;

    /// [`state_values`](Self::state_values) without the last
    /// [`BLOCK_FIELDS`](Self::BLOCK_FIELDS) (which stay as they are).
    #[inline(always)]
    fn state_values_head(state: &Self::State, out: &mut [f64]) {
        Self::state_values(state, out);
    }

    /// The last [`BLOCK_FIELDS`](Self::BLOCK_FIELDS) values of
    /// [`state_values`](Self::state_values) of each of `states`, bit for
    /// bit: `out[field][lane]`.
    #[inline(always)]
    fn block_fields<const N: usize>(
        _states: &[Self::State; N],
        _out: &mut [[f64; N]; MAX_BLOCK_FIELDS],
    ) {
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::bourg::Bourg;
    use fdm_core::palmer::Palmer;

    /// Eight states a few seconds into flights of the demonstration fleet.
    fn states<M: ColumnModel>() -> [M::State; 8] {
        let aircraft = M::default_aircraft();
        let dt = M::time_step(30.0);
        core::array::from_fn(|i| {
            let (controls, mut state) = M::fleet_member(i);
            for _ in 0..90 {
                state = M::step(&aircraft, &controls, &state, dt);
            }
            state
        })
    }

    /// The head and the lane-wise fields are the state's values, bit for
    /// bit.
    #[test]
    fn head_and_block_fields_are_the_values() {
        fn check<M: ColumnModel>() {
            let n = M::STATE_FIELDS.len();
            let head = n - M::BLOCK_FIELDS;
            assert!(M::BLOCK_FIELDS <= MAX_BLOCK_FIELDS);
            let states = states::<M>();
            let mut fields = [[0.0; 8]; MAX_BLOCK_FIELDS];
            M::block_fields(&states, &mut fields);
            for (lane, state) in states.iter().enumerate() {
                let mut all = vec![0.0; n];
                M::state_values(state, &mut all);
                let mut part = vec![f64::NAN; n];
                M::state_values_head(state, &mut part);
                for (a, b) in all[..head].iter().zip(&part[..head]) {
                    assert_eq!(a.to_bits(), b.to_bits(), "{}", M::NAME);
                }
                for (f, a) in all[head..].iter().enumerate() {
                    assert_eq!(a.to_bits(), fields[f][lane].to_bits(), "{}", M::NAME);
                }
            }
        }
        check::<Palmer>();
        check::<Bourg>();
    }

    /// Each control's value is in its range and sets the same controls
    /// back; a value in range but not allowed is refused.
    #[test]
    fn controls_round_trip() {
        fn check<M: ColumnModel>() {
            let mut values = vec![0.0; M::CONTROL_FIELDS.len()];
            for i in 0..8 {
                let (controls, _) = M::fleet_member(i);
                M::control_values(&controls, &mut values);
                for (index, (&value, &(name, low, high))) in
                    values.iter().zip(M::CONTROL_FIELDS).enumerate()
                {
                    assert!((low..=high).contains(&value), "{name} = {value}");
                    assert_eq!(M::with_control(controls, index, value), Ok(controls));
                }
            }
            for (name, _) in M::TRIM_SETS {
                assert!(M::CONTROL_FIELDS.iter().any(|c| c.0 == *name), "{name}");
            }
        }
        check::<Palmer>();
        check::<Bourg>();
        let c = Palmer::initial_controls();
        assert_eq!(
            Palmer::with_control(c, 3, 10.0),
            Err("10 is not 0, 20 or 40".to_string())
        );
        assert_eq!(
            Bourg::with_control(Bourg::initial_controls(), 1, 0.5),
            Err("0.5 is not -1, 0 or 1".to_string())
        );
    }
}
