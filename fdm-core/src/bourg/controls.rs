//! Pilot controls: thrust, rudder, ailerons, elevators, landing flaps.

use serde::{Deserialize, Serialize};

use super::airframe::{Element, Flap, DELTA_THRUST_LB, MAX_THRUST_LB, RUDDER_DEFLECTION_DEG};
use super::BourgAction;

/// Thrust at start, lb.
pub const INITIAL_THRUST_LB: f32 = 500.0;
/// Pitch-trim change per trim key press or script action (an extension, see
/// [`BourgControls::pitch_trim`]): 1 % of the full elevator deflection.
pub const PITCH_TRIM_STEP: f32 = 0.01;

/// The control settings of one frame.
///
/// The original mutates the control elements' `fIncidence` and `iFlap`
/// directly; here the controls are a value and the model reads each element's
/// setting through [`element_flap`](Self::element_flap) and
/// [`rudder_incidence_deg`](Self::rudder_incidence_deg). For Bourg's airframe
/// (all rigging neutral) this is exactly the original's behaviour.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BourgControls {
    /// Engine thrust along the body x axis, lb, in `0..=MAX_THRUST_LB` when set
    /// through [`apply`](Self::apply).
    pub thrust_lb: f32,
    /// Rudder deflection, degrees, added to element 6's rigged incidence:
    /// +16 yaw left, −16 yaw right, 0 neutral.
    pub rudder_deg: f32,
    /// Port aileron (element 0).
    pub port_aileron: Flap,
    /// Starboard aileron (element 3).
    pub starboard_aileron: Flap,
    /// Both elevators (elements 4 and 5).
    pub elevators: Flap,
    /// Landing flaps (elements 1 and 2) down.
    pub landing_flaps: bool,
    /// Persistent pitch trim, −1..=1 (an **extension** of the original,
    /// which has none): while the elevators are neutral, their lift and drag
    /// coefficients are the neutral tables' blended toward the trailing-edge-up
    /// tables (positive, nose up) or trailing-edge-down tables (negative) by
    /// `|pitch_trim|` ([`elevator_coefficients`](Self::elevator_coefficients)).
    /// At 0, the default, the model is the original, bit for bit. It is not
    /// reset at the start of a frame.
    #[serde(default)]
    pub pitch_trim: f32,
}

impl BourgControls {
    /// The original's start: thrust 500 lb, surfaces neutral, flaps up.
    #[must_use]
    pub fn initial() -> Self {
        Self {
            thrust_lb: INITIAL_THRUST_LB,
            rudder_deg: 0.0,
            port_aileron: Flap::Neutral,
            starboard_aileron: Flap::Neutral,
            elevators: Flap::Neutral,
            landing_flaps: false,
            pitch_trim: 0.0,
        }
    }

    /// One key press / script action with the original's thrust limits
    /// ([`MAX_THRUST_LB`], [`DELTA_THRUST_LB`]); see
    /// [`apply_within`](Self::apply_within).
    #[must_use]
    pub fn apply(self, action: BourgAction) -> Self {
        self.apply_within(action, MAX_THRUST_LB, DELTA_THRUST_LB)
    }

    /// One key press / script action, as the original's control functions:
    ///
    /// * thrust ± `delta_thrust_lb`, then clamped to `≤ max_thrust_lb` (up) or
    ///   `≥ 0` (down), in the original's `f32` operations;
    /// * yaw left / right: rudder +16° / −16°;
    /// * roll left: port aileron trailing edge up, starboard down; roll right the reverse;
    /// * pitch up: elevators trailing edge up; pitch down: down;
    /// * flaps down: landing flaps down (they stay); flaps up: back up.
    #[must_use]
    pub fn apply_within(
        self,
        action: BourgAction,
        max_thrust_lb: f32,
        delta_thrust_lb: f32,
    ) -> Self {
        let rudder = RUDDER_DEFLECTION_DEG;
        let mut c = self;
        match action {
            BourgAction::ThrustUp => {
                c.thrust_lb += delta_thrust_lb;
                if c.thrust_lb > max_thrust_lb {
                    c.thrust_lb = max_thrust_lb;
                }
            }
            BourgAction::ThrustDown => {
                c.thrust_lb -= delta_thrust_lb;
                if c.thrust_lb < 0.0 {
                    c.thrust_lb = 0.0;
                }
            }
            BourgAction::YawLeft => c.rudder_deg = rudder,
            BourgAction::YawRight => c.rudder_deg = -rudder,
            BourgAction::RollLeft => {
                c.port_aileron = Flap::TrailingEdgeUp;
                c.starboard_aileron = Flap::TrailingEdgeDown;
            }
            BourgAction::RollRight => {
                c.port_aileron = Flap::TrailingEdgeDown;
                c.starboard_aileron = Flap::TrailingEdgeUp;
            }
            BourgAction::PitchUp => c.elevators = Flap::TrailingEdgeUp,
            BourgAction::PitchDown => c.elevators = Flap::TrailingEdgeDown,
            BourgAction::FlapsDown => c.landing_flaps = true,
            BourgAction::FlapsUp => c.landing_flaps = false,
            BourgAction::TrimNoseUp | BourgAction::TrimNoseDown => {
                let step = PITCH_TRIM_STEP;
                let t = if action == BourgAction::TrimNoseUp {
                    c.pitch_trim + step
                } else {
                    c.pitch_trim - step
                };
                // Comparisons as before the f32-only rewrite (the same
                // values as `clamp`, NaN included).
                #[allow(clippy::manual_clamp)]
                let clamped = if t > 1.0 {
                    1.0
                } else if t < -1.0 {
                    -1.0
                } else {
                    t
                };
                c.pitch_trim = clamped;
            }
        }
        c
    }

    /// The lift and drag coefficients of element `index` at `angle_deg`:
    /// the airfoil table of [`element_flap`](Self::element_flap), except for
    /// the elevators (elements 4 and 5) with a nonzero
    /// [`pitch_trim`](Self::pitch_trim) while no pitch key deflects them:
    /// then `c + (c_deflected − c)·|trim|` for CL and CD, with the
    /// trailing-edge-up tables for a positive trim, trailing-edge-down for a
    /// negative one (|trim| clamped to 1). With zero trim this is exactly
    /// `airfoil_coefficients(angle, element_flap(index, element))`.
    #[inline]
    #[must_use]
    pub fn elevator_coefficients(
        &self,
        index: usize,
        element: &Element,
        angle_deg: f32,
    ) -> (f32, f32) {
        let base =
            super::airfoil::airfoil_coefficients(angle_deg, self.element_flap(index, element));
        if !matches!(index, 4 | 5) || self.elevators != Flap::Neutral || self.pitch_trim == 0.0 {
            return base;
        }
        let (flap, t) = self.trim_tables();
        let (cl, cd) = super::airfoil::airfoil_coefficients(angle_deg, flap);
        (base.0 + (cl - base.0) * t, base.1 + (cd - base.1) * t)
    }

    /// The pitch trim's tables and blend factor for
    /// [`elevator_coefficients`](Self::elevator_coefficients):
    /// trailing-edge-up and `trim` for a positive trim, trailing-edge-down
    /// and `−trim` otherwise, the factor clamped to 1 (NaN kept).
    #[inline]
    pub(crate) fn trim_tables(&self) -> (Flap, f32) {
        let (flap, mut t) = if self.pitch_trim > 0.0 {
            (Flap::TrailingEdgeUp, self.pitch_trim)
        } else {
            (Flap::TrailingEdgeDown, -self.pitch_trim)
        };
        if t > 1.0 {
            t = 1.0;
        }
        (flap, t)
    }

    /// Rudder, ailerons and elevators back to neutral (done at the start of
    /// every frame, before the frame's key presses); thrust and landing flaps
    /// keep their settings.
    #[must_use]
    pub fn neutralize_surfaces(self) -> Self {
        Self {
            rudder_deg: 0.0,
            port_aileron: Flap::Neutral,
            starboard_aileron: Flap::Neutral,
            elevators: Flap::Neutral,
            ..self
        }
    }

    /// The airfoil table element `index` flies with: the control's setting for
    /// a control surface that is deflected (ailerons 0 and 3, landing flaps 1
    /// and 2, elevators 4 and 5), otherwise the element's rigged
    /// [`Element::flap`].
    #[inline]
    #[must_use]
    pub fn element_flap(&self, index: usize, element: &Element) -> Flap {
        let control = match index {
            0 => self.port_aileron,
            3 => self.starboard_aileron,
            1 | 2 if self.landing_flaps => Flap::TrailingEdgeDown,
            4 | 5 => self.elevators,
            _ => Flap::Neutral,
        };
        if control == Flap::Neutral {
            element.flap
        } else {
            control
        }
    }

    /// The rudder's (element 6's) current incidence, degrees: its rigging plus
    /// [`rudder_deg`](Self::rudder_deg).
    #[inline]
    #[must_use]
    pub fn rudder_incidence_deg(&self, rudder: &Element) -> f32 {
        rudder.incidence_deg + self.rudder_deg
    }
}

impl Default for BourgControls {
    fn default() -> Self {
        Self::initial()
    }
}
