//! What a learning agent's tasks need of a model: how the agent's actions
//! (numbers in -1..1) set the model's controls, which controls the agent
//! observes, and the altitude, climb rate and velocity the tasks read of
//! the state. These are the Gymnasium tasks of the Python package
//! (`afit_fdm.gym`, computed in Rust by `afit-fdm-py`'s `task` module),
//! whose Python oracle (`afit-fdm-py/tests/test_task_kernel.py`) checks
//! them bit for bit; the formulas here are that oracle's, with the same
//! operations in the same order.
//!
//! Each model implements [`AgentModel`] in its adapter module
//! ([`super::palmer`], [`super::bourg`]). The Gymnasium vector environment
//! calls these for every aircraft at every step, so the implementations are
//! `#[inline]` or `#[inline(always)]` as they were in the binding.

use super::columns::ColumnModel;

/// Feet per metre, as `afit_fdm.gym` computes it (`1.0 / 0.3048`).
pub const FT_PER_M: f64 = 1.0 / 0.3048;

/// What the tasks read of one aircraft's state, in the units of
/// `afit_fdm.gym`'s `_kinematics`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics {
    /// Altitude, ft.
    pub altitude_ft: f64,
    /// Climb rate, ft/s.
    pub climb_ftps: f64,
    /// North velocity in the model's unit per second (Palmer m/s, Bourg
    /// ft/s): see [`AgentModel::GROUND_MPS_PER_SPEED`].
    pub vx: f64,
    /// West velocity in the same unit.
    pub vy: f64,
}

/// A model as the agent's tasks act on and observe it.
pub trait AgentModel: ColumnModel {
    /// Actions per aircraft of the tasks (at most 8).
    const TASK_ACTIONS: usize;

    /// Observed controls per aircraft of the tasks (at most 5).
    const TASK_CONTROL_OBS: usize;

    /// The horizontal speed in the velocity's units times this is the
    /// ground speed in m/s (Palmer 1, Bourg 0.3048).
    const GROUND_MPS_PER_SPEED: f64;

    /// What the tasks read of the state (altitude, climb rate, velocity),
    /// from its [`ColumnModel::state_values`] (or
    /// [`ColumnModel::state_values_head`]: the fields it reads are there).
    fn task_kinematics(values: &[f64]) -> Kinematics;

    /// `out` (of [`TASK_CONTROL_OBS`](Self::TASK_CONTROL_OBS) values)
    /// becomes the observed controls, from the controls'
    /// [`ColumnModel::control_values`].
    fn task_control_obs(values: &[f64], out: &mut [f64]);

    /// The controls one aircraft's actions (clipped to -1..1) set, as
    /// `(control index, value)`, in the order the tasks set them; the first
    /// `.1` entries are used.
    fn task_controls(actions: &[f64]) -> ([(usize, f64); 5], usize);

    /// `controls` with the controls one aircraft's actions (clipped to
    /// -1..1, NaN only where a threshold reads it) set: what setting each
    /// of [`task_controls`](Self::task_controls) with
    /// [`ColumnModel::with_control`] gives, without the checks those values
    /// cannot fail.
    fn task_apply(controls: Self::Controls, actions: &[f64]) -> Self::Controls;
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::bourg::Bourg;
    use fdm_core::model::Model;
    use fdm_core::palmer::Palmer;

    /// Actions over -1..1, with the thresholds ±1/3 and their neighbours.
    fn action_values() -> Vec<f64> {
        let third = 1.0_f64 / 3.0;
        let mut v: Vec<f64> = (0..=20).map(|i| -1.0 + 0.1 * f64::from(i)).collect();
        for t in [-third, third] {
            v.extend([t, t.next_down(), t.next_up()]);
        }
        v
    }

    /// `task_apply` is setting each of `task_controls` with `with_control`,
    /// and every such value is in its control's range.
    #[test]
    fn apply_is_the_listed_controls() {
        fn check<M: AgentModel>() {
            assert!(M::TASK_ACTIONS <= 8 && M::TASK_CONTROL_OBS <= 5);
            let values = action_values();
            let start = M::initial_controls();
            for i in 0..values.len() {
                // A different value per action: each action's own effect.
                let actions: Vec<f64> = (0..M::TASK_ACTIONS)
                    .map(|k| values[(i + 7 * k) % values.len()])
                    .collect();
                let (list, count) = M::task_controls(&actions);
                let mut expected = start;
                for &(index, value) in &list[..count] {
                    let (name, low, high) = M::CONTROL_FIELDS[index];
                    assert!((low..=high).contains(&value), "{name} = {value}");
                    expected = M::with_control(expected, index, value).unwrap();
                }
                assert_eq!(M::task_apply(start, &actions), expected, "{actions:?}");
            }
        }
        check::<Palmer>();
        check::<Bourg>();
    }

    /// The kinematics are the state's position and velocity columns.
    #[test]
    fn kinematics_read_the_columns() {
        let mut v = vec![0.0; Palmer::STATE_FIELDS.len()];
        Palmer::state_values(&Palmer::fleet_member(3).1, &mut v);
        let k = Palmer::task_kinematics(&v);
        assert_eq!(k.altitude_ft, v[3] * FT_PER_M);
        assert_eq!((k.vx, k.vy, k.climb_ftps), (v[4], v[5], v[6] * FT_PER_M));
        let mut v = vec![0.0; Bourg::STATE_FIELDS.len()];
        Bourg::state_values(&Bourg::fleet_member(3).1, &mut v);
        let k = Bourg::task_kinematics(&v);
        assert_eq!(
            (k.altitude_ft, k.climb_ftps, k.vx, k.vy),
            (v[3], v[6], v[4], v[5])
        );
    }
}
