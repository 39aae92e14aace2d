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

use fdm_core::real::kernel::{Array, Block};
use fdm_core::real::{LaneModel, Real};

use super::columns::{ColumnModel, MAX_BLOCK_FIELDS};

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

/// Most observed controls per aircraft ([`AgentModel::TASK_CONTROL_OBS`]).
pub const MAX_CONTROL_OBS: usize = 5;

/// Most actions per aircraft ([`AgentModel::TASK_ACTIONS`]).
pub const MAX_ACTIONS: usize = 8;

/// Most state fields ([`ColumnModel::STATE_FIELDS`]) a block reads at once.
pub const MAX_STATE_FIELDS: usize = 32;

/// What the tasks read of a fleet's aircraft, a block of the fleet's lanes
/// at a time (`fdm_core::real::kernel::Block`): the state's columns, the
/// kinematics and the observed controls.
/// Each method's result is, lane by lane, the per-aircraft method's, bit
/// for bit (the provided bodies are those methods lane by lane; a model may
/// compute its lanes together). Lane `l < count` is an aircraft; the lanes
/// past `count` (the fleet's last block) are read along where that is
/// simpler.
pub trait LaneAgent: AgentModel + LaneModel {
    /// Whether a reader should read a block at a time with these methods
    /// rather than one aircraft at a time: `true` where the model computes
    /// them for the lanes together (the provided bodies, a lane at a time
    /// through a state's values, are slower than reading each aircraft's
    /// state once).
    const BLOCK_READS: bool = false;

    /// `out[f].as_mut()[l]` becomes field `f` of
    /// [`ColumnModel::state_values_head`] of lane `l` of `block`, for the
    /// first `out.len()` fields (at most the fields before the last
    /// [`ColumnModel::BLOCK_FIELDS`] and [`MAX_STATE_FIELDS`]) and the lanes
    /// below `count` (a model may write the other lanes too).
    #[inline(always)]
    fn block_state_values(block: &Block<Self>, count: usize, out: &mut [Array<Self, f64>]) {
        let mut values = [0.0; MAX_STATE_FIELDS];
        let values = &mut values[..Self::STATE_FIELDS.len()];
        for lane in 0..count {
            Self::state_values_head(&block.state(lane), values);
            for (column, v) in out.iter_mut().zip(values.iter()) {
                column.as_mut()[lane] = *v;
            }
        }
    }

    /// `out[k].as_mut()[l]` becomes the `k`-th of the last
    /// [`ColumnModel::BLOCK_FIELDS`] values of
    /// [`ColumnModel::state_values`] (those [`ColumnModel::block_fields`]
    /// computes) of lane `l` of `block`, for the lanes below `count` (a model
    /// may write the other lanes too) and `k` below
    /// [`ColumnModel::BLOCK_FIELDS`].
    #[inline(always)]
    fn block_tail_values(
        block: &Block<Self>,
        count: usize,
        out: &mut [Array<Self, f64>; MAX_BLOCK_FIELDS],
    ) {
        let mut values = [0.0; MAX_STATE_FIELDS];
        let values = &mut values[..Self::STATE_FIELDS.len()];
        let head = Self::STATE_FIELDS.len() - Self::BLOCK_FIELDS;
        for lane in 0..count {
            Self::state_values(&block.state(lane), values);
            for (column, v) in out.iter_mut().zip(&values[head..]) {
                column.as_mut()[lane] = *v;
            }
        }
    }

    /// `out` becomes [`AgentModel::task_kinematics`] of each lane of
    /// `columns` (what [`Self::block_state_values`] gives; lane `l`'s
    /// values are `columns[f].as_ref()[l]`), field by field: altitude, climb
    /// rate, `vx`, `vy`.
    #[inline(always)]
    fn block_kinematics(columns: &[Array<Self, f64>], out: &mut [Array<Self, f64>; 4]) {
        let mut values = [0.0; MAX_STATE_FIELDS];
        let values = &mut values[..columns.len()];
        for lane in 0..Self::Lanes::LANES {
            for (v, column) in values.iter_mut().zip(columns) {
                *v = column.as_ref()[lane];
            }
            let k = Self::task_kinematics(values);
            for (o, v) in out
                .iter_mut()
                .zip([k.altitude_ft, k.climb_ftps, k.vx, k.vy])
            {
                o.as_mut()[lane] = v;
            }
        }
    }

    /// `out[k].as_mut()[l]` becomes observed control `k`
    /// ([`AgentModel::task_control_obs`] of [`ColumnModel::control_values`])
    /// of lane `l` of `controls`, for the lanes below `count` (a model may
    /// write the other lanes too) and `k` below
    /// [`AgentModel::TASK_CONTROL_OBS`].
    #[inline(always)]
    fn block_control_obs(
        controls: &Array<Self, Self::Controls>,
        count: usize,
        out: &mut [Array<Self, f64>; MAX_CONTROL_OBS],
    ) {
        let mut values = [0.0; MAX_ACTIONS];
        let values = &mut values[..Self::CONTROL_FIELDS.len()];
        let mut observed = [0.0; MAX_CONTROL_OBS];
        let observed = &mut observed[..Self::TASK_CONTROL_OBS];
        for (lane, c) in controls.as_ref().iter().enumerate().take(count) {
            Self::control_values(c, values);
            Self::task_control_obs(values, observed);
            for (column, v) in out.iter_mut().zip(observed.iter()) {
                column.as_mut()[lane] = *v;
            }
        }
    }
}

/// The glider `sim-cli glider` flies (its one model file, included as
/// fdm-fleet's `tests/third_model.rs` includes it), for the tests: a model
/// that keeps [`LaneAgent`]'s provided bodies, which Palmer and Bourg
/// override.
#[cfg(test)]
#[path = "../../../sim-cli/src/models/glider/model.rs"]
mod glider;

#[cfg(test)]
mod tests {
    use super::glider::{Glider, GliderControls, GliderState};
    use super::*;
    use crate::model::columns::ControlRange;
    use fdm_core::bourg::Bourg;
    use fdm_core::model::Model;
    use fdm_core::palmer::Palmer;
    use fdm_core::real::Lanes;

    /// The glider's speed and climb angle (degrees): the fields a program
    /// may compute a block at a time ([`ColumnModel::BLOCK_FIELDS`]).
    fn glider_tail(s: &GliderState) -> [f64; 2] {
        let v = s.velocity_mps;
        [v.norm(), v.z.atan2(v.x.hypot(v.y)).to_degrees()]
    }

    /// The glider's columns, Palmer's state layout (time, position,
    /// velocity) and two derived fields: a model whose block fields are not
    /// the whole state (the head is 7 of 9 fields).
    impl ColumnModel for Glider {
        const STATE_FIELDS: &'static [&'static str] = &[
            "time_s",
            "x_m",
            "y_m",
            "z_m",
            "vx_mps",
            "vy_mps",
            "vz_mps",
            "speed_mps",
            "climb_deg",
        ];
        const CONTROL_FIELDS: &'static [ControlRange] =
            &[("lift_coefficient", 0.0, 1.4), ("bank_deg", -45.0, 45.0)];
        const TRIM_SETS: &'static [(&'static str, &'static str)] = &[];
        const BLOCK_FIELDS: usize = 2;

        fn state_values(s: &GliderState, out: &mut [f64]) {
            Self::state_values_head(s, out);
            out[7..].copy_from_slice(&glider_tail(s));
        }

        fn state_values_head(s: &GliderState, out: &mut [f64]) {
            let (p, v) = (s.position_m, s.velocity_mps);
            out[..7].copy_from_slice(&[s.time_s, p.x, p.y, p.z, v.x, v.y, v.z]);
        }

        fn block_fields<const N: usize>(
            states: &[GliderState; N],
            out: &mut [[f64; N]; MAX_BLOCK_FIELDS],
        ) {
            for (lane, s) in states.iter().enumerate() {
                let [speed, climb] = glider_tail(s);
                (out[0][lane], out[1][lane]) = (speed, climb);
            }
        }

        fn control_values(c: &GliderControls, out: &mut [f64]) {
            out.copy_from_slice(&[c.lift_coefficient, c.bank_deg]);
        }

        fn with_control(
            mut c: GliderControls,
            index: usize,
            value: f64,
        ) -> Result<GliderControls, String> {
            match index {
                0 => c.lift_coefficient = value,
                _ => c.bank_deg = value,
            }
            Ok(c)
        }
    }

    /// The glider's tasks: two actions (lift coefficient over its range,
    /// bank), both controls observed over their ranges.
    impl AgentModel for Glider {
        const TASK_ACTIONS: usize = 2;
        const TASK_CONTROL_OBS: usize = 2;
        const GROUND_MPS_PER_SPEED: f64 = 1.0;

        fn task_kinematics(v: &[f64]) -> Kinematics {
            Kinematics {
                altitude_ft: v[3] * FT_PER_M,
                climb_ftps: v[6] * FT_PER_M,
                vx: v[4],
                vy: v[5],
            }
        }

        fn task_control_obs(c: &[f64], out: &mut [f64]) {
            out.copy_from_slice(&[c[0] / 1.4, c[1] / 45.0]);
        }

        fn task_controls(a: &[f64]) -> ([(usize, f64); 5], usize) {
            let none = (0, 0.0);
            let list = [(0, 0.7 * (a[0] + 1.0)), (1, 45.0 * a[1])];
            ([list[0], list[1], none, none, none], 2)
        }

        fn task_apply(mut c: GliderControls, a: &[f64]) -> GliderControls {
            let ([(_, lift), (_, bank), ..], _) = Self::task_controls(a);
            (c.lift_coefficient, c.bank_deg) = (lift, bank);
            c
        }
    }

    /// Every provided body.
    impl LaneAgent for Glider {}

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
        check::<Glider>();
    }

    /// A block of `M` with a different flight in each lane (a few seconds
    /// into the demonstration fleet's members), and each lane's controls.
    fn block<M: LaneAgent>() -> Block<M> {
        let aircraft = M::default_aircraft();
        let dt = M::time_step(30.0);
        let mut block = Block::<M>::idle(&aircraft);
        for lane in 0..M::Lanes::LANES {
            let (controls, mut state) = M::fleet_member(lane);
            for _ in 0..(30 + lane) {
                state = M::step(&aircraft, &controls, &state, dt);
            }
            block.set_state(lane, &state);
            block.controls.as_mut()[lane] = controls;
        }
        block
    }

    /// A block of Bourg aircraft at the edges of the state views: pitch
    /// ±90° and near it (the Euler angles' singular path), steep pitch
    /// (the lane `asin` past 0.5), a stalled aircraft, ±0, NaN, infinite and
    /// huge components, a zero quaternion; the other lanes as [`block`].
    fn bourg_edge_block() -> Block<Bourg> {
        use fdm_core::bourg::ops::quat_from_euler_deg;
        use nalgebra::{Quaternion, Vector3};
        let mut block = block::<Bourg>();
        let pitched = |p: f32| quat_from_euler_deg(&Vector3::new(10.0, p, 30.0));
        for (lane, edit) in [
            (0, 0_u8),
            (1, 1),
            (2, 2),
            (3, 3),
            (5, 4),
            (7, 5),
            (8, 6),
            (10, 7),
            (12, 8),
            (15, 9),
        ] {
            let mut s = block.state(lane);
            match edit {
                0 => s.orientation = pitched(90.0),
                1 => s.orientation = pitched(-90.0),
                2 => s.orientation = pitched(89.99),
                3 => s.orientation = pitched(-40.0),
                4 => {
                    s.stalling = true;
                    s.velocity_ftps = Vector3::new(-0.0, 0.0, -0.0);
                }
                5 => {
                    s.velocity_ftps.x = f32::NAN;
                    s.orientation.coords.y = f32::NAN;
                }
                6 => {
                    s.velocity_ftps.y = f32::INFINITY;
                    s.angular_velocity_radps.z = -0.0;
                }
                7 => s.velocity_ftps = Vector3::new(1e30, -1e30, 3e-45),
                8 => s.orientation = Quaternion::new(0.0, 0.0, 0.0, 0.0),
                _ => s.orientation = pitched(75.0),
            }
            block.set_state(lane, &s);
        }
        block
    }

    /// The block forms are the per-aircraft methods lane by lane, bit for
    /// bit, for whole and partial blocks (the lanes below `count`), of
    /// flights and (Bourg) of a block at the edges ([`bourg_edge_block`]).
    #[test]
    fn lane_agent_is_the_per_aircraft_methods() {
        fn check<M: LaneAgent>(block: &Block<M>) {
            let lanes = M::Lanes::LANES;
            let head = M::STATE_FIELDS.len() - M::BLOCK_FIELDS;
            for count in [lanes, lanes - 1, 3, 1] {
                let sentinel = -12345.0_f64;
                let fill = || M::Lanes::array(|_| sentinel);
                // The state's columns.
                let mut columns: Vec<Array<M, f64>> = (0..head).map(|_| fill()).collect();
                M::block_state_values(block, count, &mut columns);
                for lane in 0..lanes {
                    let mut want = vec![0.0; M::STATE_FIELDS.len()];
                    M::state_values_head(&block.state(lane), &mut want);
                    for (f, column) in columns.iter().enumerate() {
                        let got = column.as_ref()[lane];
                        if lane < count {
                            assert_eq!(got.to_bits(), want[f].to_bits(), "{} field {f}", M::NAME);
                        }
                    }
                }
                // The derived fields.
                let mut tail: [Array<M, f64>; MAX_BLOCK_FIELDS] = core::array::from_fn(|_| fill());
                M::block_tail_values(block, count, &mut tail);
                for lane in 0..count {
                    let mut want = vec![0.0; M::STATE_FIELDS.len()];
                    M::state_values(&block.state(lane), &mut want);
                    for (k, column) in tail.iter().enumerate().take(M::BLOCK_FIELDS) {
                        let got = column.as_ref()[lane];
                        assert_eq!(
                            got.to_bits(),
                            want[head + k].to_bits(),
                            "{} lane {lane} field {}",
                            M::NAME,
                            head + k
                        );
                    }
                }
                // The kinematics of the whole block's columns.
                let mut all: Vec<Array<M, f64>> = (0..head).map(|_| fill()).collect();
                M::block_state_values(block, lanes, &mut all);
                let mut kinematics: [Array<M, f64>; 4] = core::array::from_fn(|_| fill());
                M::block_kinematics(&all, &mut kinematics);
                for lane in 0..lanes {
                    let mut v = vec![0.0; M::STATE_FIELDS.len()];
                    M::state_values(&block.state(lane), &mut v);
                    let k = M::task_kinematics(&v);
                    let want = [k.altitude_ft, k.climb_ftps, k.vx, k.vy];
                    for (f, w) in want.iter().enumerate() {
                        assert_eq!(
                            kinematics[f].as_ref()[lane].to_bits(),
                            w.to_bits(),
                            "{}",
                            M::NAME
                        );
                    }
                }
                // The observed controls.
                let mut observed: [Array<M, f64>; MAX_CONTROL_OBS] =
                    core::array::from_fn(|_| fill());
                M::block_control_obs(&block.controls, count, &mut observed);
                for lane in 0..count {
                    let mut c = vec![0.0; M::CONTROL_FIELDS.len()];
                    M::control_values(&block.controls.as_ref()[lane], &mut c);
                    let mut want = vec![0.0; M::TASK_CONTROL_OBS];
                    M::task_control_obs(&c, &mut want);
                    for (k, w) in want.iter().enumerate() {
                        assert_eq!(
                            observed[k].as_ref()[lane].to_bits(),
                            w.to_bits(),
                            "{}",
                            M::NAME
                        );
                    }
                }
            }
        }
        check::<Palmer>(&block::<Palmer>());
        check::<Bourg>(&block::<Bourg>());
        check::<Bourg>(&bourg_edge_block());
        // The provided bodies (Palmer and Bourg override every one), with
        // each lane's own controls: the glider keeps them all.
        const { assert!(!<Glider as LaneAgent>::BLOCK_READS) };
        let mut gliders = block::<Glider>();
        for (lane, c) in gliders.controls.as_mut().iter_mut().enumerate() {
            let k = f64::from(u8::try_from(lane).unwrap());
            c.lift_coefficient = 0.3 + 0.07 * k;
            c.bank_deg = -30.0 + 6.0 * k;
        }
        check::<Glider>(&gliders);
    }

    /// The tasks' feet are international feet (0.3048 m): a Palmer state
    /// 304.8 m up climbing at 3.048 m/s is 1000 ft up climbing at 10 ft/s
    /// (to the rounding of the metres).
    #[test]
    fn the_tasks_feet_are_0_3048_m() {
        let (_, mut s) = Palmer::fleet_member(3);
        s.position_m.z = 304.8;
        s.velocity_mps.z = 3.048;
        let mut v = vec![0.0; Palmer::STATE_FIELDS.len()];
        Palmer::state_values(&s, &mut v);
        let k = Palmer::task_kinematics(&v);
        assert!((k.altitude_ft - 1000.0).abs() < 1e-9, "{k:?}");
        assert!((k.climb_ftps - 10.0).abs() < 1e-12, "{k:?}");
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
