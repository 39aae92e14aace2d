//! Frames: from one aircraft's geodetic position, local north-east-down (NED)
//! attitude and velocity to DIS's Earth-centred, Earth-fixed (ECEF) world
//! frame, and back.
//!
//! * **ECEF** (DIS "world coordinates"): origin at the Earth's centre, x
//!   towards latitude 0 / longitude 0, y towards latitude 0 / longitude 90° E,
//!   z towards the north pole; metres.
//! * **Local NED** at a geodetic latitude φ / longitude λ: north, east and
//!   down along the WGS-84 ellipsoid normal. In ECEF components its axes are
//!   `N = (-sin φ cos λ, -sin φ sin λ, cos φ)`, `E = (-sin λ, cos λ, 0)`,
//!   `D = (-cos φ cos λ, -cos φ sin λ, -sin φ)`; the matrix with these three
//!   columns, [`ned_to_ecef_rotation`], maps NED components to ECEF ones.
//! * **Body**: x forward, y right wing, z down. The attitude
//!   (heading ψₙ, pitch θₙ, roll φₙ, the aerospace Z-Y-X sequence relative to
//!   local NED) gives `C_ned←body = Rz(ψₙ) · Ry(θₙ) · Rx(φₙ)`.
//! * **DIS orientation**: the same Z-Y-X sequence, but relative to the ECEF
//!   axes: `C_ecef←body = Rz(ψ) · Ry(θ) · Rx(φ)`. So
//!   `C_ecef←body = C_ecef←ned(φ, λ) · C_ned←body`, and ψ, θ, φ are read
//!   back from that product ([`DisEuler::from_body_to_ecef`]).

use fdm_core::math;
use nalgebra::{Matrix3, Vector3};

use crate::error::DisOutputError;
use crate::geodesy::{
    ecef_to_geodetic, enu_to_ecef_rotation, geodetic_to_ecef, Attitude, Geodetic,
};

/// One aircraft's state for one frame, as a flight model shell has it.
///
/// All angles in degrees, distances in metres, times in seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AircraftState {
    /// Simulation time of this state, seconds (any origin; it drives the
    /// dead-reckoning clock and the PDU timestamp).
    pub time_s: f64,
    /// WGS-84 geodetic position: latitude/longitude in degrees, height above
    /// the ellipsoid in metres.
    pub position: Geodetic,
    /// Heading (clockwise from true north), pitch (nose up +) and roll (right
    /// wing down +) relative to the local NED frame at `position`, degrees.
    pub attitude: Attitude,
    /// Velocity relative to the Earth in local NED components, m/s.
    pub velocity_ned_m_s: Vector3<f64>,
    /// Angular velocity of the body relative to the Earth, in body axes
    /// (roll rate p, pitch rate q, yaw rate r), rad/s. `None` sends zeros.
    pub angular_velocity_body_rad_s: Option<Vector3<f64>>,
    /// Acceleration relative to the Earth in local NED components, m/s².
    /// `None` sends zeros.
    pub acceleration_ned_m_s2: Option<Vector3<f64>>,
}

impl AircraftState {
    /// A state with no angular velocity and no acceleration.
    #[must_use]
    pub fn new(
        time_s: f64,
        position: Geodetic,
        attitude: Attitude,
        velocity_ned_m_s: Vector3<f64>,
    ) -> Self {
        Self {
            time_s,
            position,
            attitude,
            velocity_ned_m_s,
            angular_velocity_body_rad_s: None,
            acceleration_ned_m_s2: None,
        }
    }

    /// Checks that every number is finite and the latitude is in `[-90, 90]`.
    ///
    /// # Errors
    /// [`DisOutputError::NonFinite`] naming the first bad field, or
    /// [`DisOutputError::LatitudeOutOfRange`].
    pub fn validate(&self) -> Result<(), DisOutputError> {
        let scalars = [
            ("time_s", self.time_s),
            ("position.lat_deg", self.position.lat_deg),
            ("position.lon_deg", self.position.lon_deg),
            ("position.alt_m", self.position.alt_m),
            ("attitude.heading_deg", self.attitude.heading_deg),
            ("attitude.pitch_deg", self.attitude.pitch_deg),
            ("attitude.roll_deg", self.attitude.roll_deg),
        ];
        for (name, v) in scalars {
            if !v.is_finite() {
                return Err(DisOutputError::NonFinite(name));
            }
        }
        let vectors = [
            ("velocity_ned_m_s", Some(self.velocity_ned_m_s)),
            (
                "angular_velocity_body_rad_s",
                self.angular_velocity_body_rad_s,
            ),
            ("acceleration_ned_m_s2", self.acceleration_ned_m_s2),
        ];
        for (name, v) in vectors {
            if let Some(v) = v {
                if !v.iter().all(|c| c.is_finite()) {
                    return Err(DisOutputError::NonFinite(name));
                }
            }
        }
        if !(-90.0..=90.0).contains(&self.position.lat_deg) {
            return Err(DisOutputError::LatitudeOutOfRange(self.position.lat_deg));
        }
        Ok(())
    }

    /// The state in DIS's world frame.
    ///
    /// # Errors
    /// As [`AircraftState::validate`].
    pub fn to_ecef(&self) -> Result<EcefState, DisOutputError> {
        self.validate()?;
        let c_en = ned_to_ecef_rotation(self.position.lat_deg, self.position.lon_deg);
        let body_to_ecef = c_en * self.attitude.body_to_ned();
        Ok(EcefState {
            time_s: self.time_s,
            location_m: geodetic_to_ecef(self.position),
            orientation: DisEuler::from_body_to_ecef(&body_to_ecef),
            body_to_ecef,
            velocity_m_s: c_en * self.velocity_ned_m_s,
            acceleration_m_s2: c_en * self.acceleration_ned_m_s2.unwrap_or_else(Vector3::zeros),
            angular_velocity_body_rad_s: self
                .angular_velocity_body_rad_s
                .unwrap_or_else(Vector3::zeros),
        })
    }
}

/// DIS orientation: Z-Y-X Euler angles of the body axes relative to the ECEF
/// axes, radians (the Entity State PDU's ψ, θ, φ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DisEuler {
    /// ψ, rotation about ECEF z, in `[-π, π]`.
    pub psi_rad: f64,
    /// θ, rotation about the once-rotated y axis, in `[-π/2, π/2]`.
    pub theta_rad: f64,
    /// φ, rotation about the body x axis, in `[-π, π]`.
    pub phi_rad: f64,
}

impl DisEuler {
    /// `C_ecef←body = Rz(ψ) · Ry(θ) · Rx(φ)`: its columns are the body's
    /// x, y, z axes in ECEF components.
    #[must_use]
    pub fn body_to_ecef(&self) -> Matrix3<f64> {
        let (s_psi, c_psi) = math::sin_cos(self.psi_rad);
        let (s_th, c_th) = math::sin_cos(self.theta_rad);
        let (s_phi, c_phi) = math::sin_cos(self.phi_rad);
        let rz = Matrix3::new(c_psi, -s_psi, 0.0, s_psi, c_psi, 0.0, 0.0, 0.0, 1.0);
        let ry = Matrix3::new(c_th, 0.0, s_th, 0.0, 1.0, 0.0, -s_th, 0.0, c_th);
        let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, c_phi, -s_phi, 0.0, s_phi, c_phi);
        rz * ry * rx
    }

    /// The angles of a body-to-ECEF rotation matrix.
    ///
    /// `θ = atan2(-c₂₀, √(c₀₀² + c₁₀²))`, `ψ = atan2(c₁₀, c₀₀)`,
    /// `φ = atan2(c₂₁, c₂₂)`. At θ = ±90° (body x along ECEF ±z: for example
    /// a level aircraft heading north on the equator) ψ and φ are not
    /// separable; φ is then 0 and the whole rotation about z goes into ψ,
    /// `ψ = atan2(-c₀₁, c₁₁)`, which describes the same rotation. That is
    /// taken wherever cos θ = √(c₀₀² + c₁₀²) is 1e-12 or less, where the
    /// general formulas would divide rounding errors by each other. Never
    /// panics.
    #[must_use]
    pub fn from_body_to_ecef(c: &Matrix3<f64>) -> Self {
        let cos_theta = math::hypot(c[(0, 0)], c[(1, 0)]);
        let theta = math::atan2(-c[(2, 0)], cos_theta);
        let (phi, psi) = if cos_theta > 1e-12 {
            (
                math::atan2(c[(2, 1)], c[(2, 2)]),
                math::atan2(c[(1, 0)], c[(0, 0)]),
            )
        } else {
            (0.0, math::atan2(-c[(0, 1)], c[(1, 1)]))
        };
        Self {
            psi_rad: psi,
            theta_rad: theta,
            phi_rad: phi,
        }
    }
}

/// One aircraft's state in DIS's world frame (what an Entity State PDU
/// carries, before rounding to the wire's `f32`s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EcefState {
    /// Simulation time, seconds.
    pub time_s: f64,
    /// Location, ECEF metres.
    pub location_m: Vector3<f64>,
    /// Orientation, DIS Euler angles relative to ECEF.
    pub orientation: DisEuler,
    /// The same orientation as a matrix (body axes as columns, ECEF
    /// components), used for orientation errors.
    pub body_to_ecef: Matrix3<f64>,
    /// Velocity relative to the Earth, ECEF components, m/s.
    pub velocity_m_s: Vector3<f64>,
    /// Acceleration relative to the Earth, ECEF components, m/s² (zero when
    /// the input had none).
    pub acceleration_m_s2: Vector3<f64>,
    /// Angular velocity in body axes, rad/s (zero when the input had none).
    pub angular_velocity_body_rad_s: Vector3<f64>,
}

impl EcefState {
    /// A state given directly in ECEF (for shells that have ECEF already,
    /// which saves the geodetic round trip of [`AircraftState::to_ecef`]):
    /// the orientation's DIS angles are read from `body_to_ecef`.
    #[must_use]
    pub fn new(
        time_s: f64,
        location_m: Vector3<f64>,
        body_to_ecef: Matrix3<f64>,
        velocity_m_s: Vector3<f64>,
        acceleration_m_s2: Vector3<f64>,
        angular_velocity_body_rad_s: Vector3<f64>,
    ) -> Self {
        Self {
            time_s,
            location_m,
            orientation: DisEuler::from_body_to_ecef(&body_to_ecef),
            body_to_ecef,
            velocity_m_s,
            acceleration_m_s2,
            angular_velocity_body_rad_s,
        }
    }

    /// Checks that every number is finite.
    ///
    /// # Errors
    /// [`DisOutputError::NonFinite`] naming the first bad field.
    pub fn validate(&self) -> Result<(), DisOutputError> {
        let fields: [(&'static str, &[f64]); 6] = [
            ("time_s", &[self.time_s]),
            ("location_m", self.location_m.as_slice()),
            ("body_to_ecef", self.body_to_ecef.as_slice()),
            ("velocity_m_s", self.velocity_m_s.as_slice()),
            ("acceleration_m_s2", self.acceleration_m_s2.as_slice()),
            (
                "angular_velocity_body_rad_s",
                self.angular_velocity_body_rad_s.as_slice(),
            ),
        ];
        for (name, values) in fields {
            if !values.iter().all(|v| v.is_finite()) {
                return Err(DisOutputError::NonFinite(name));
            }
        }
        Ok(())
    }
}

/// The NED-to-ECEF rotation at a geodetic latitude/longitude (degrees): its
/// columns are the local north, east and down unit vectors in ECEF
/// components. Its transpose maps ECEF components to NED.
#[must_use]
pub fn ned_to_ecef_rotation(lat_deg: f64, lon_deg: f64) -> Matrix3<f64> {
    // The geodesy module gives east, north, up as columns; NED is
    // (north, east, -up).
    let enu = enu_to_ecef_rotation(lat_deg, lon_deg);
    Matrix3::from_columns(&[enu.column(1).into(), enu.column(0).into(), -enu.column(2)])
}

/// What a receiver recovers from a DIS location and orientation: the
/// geodetic position and the attitude relative to local NED there.
///
/// Non-finite input gives NaN fields; never panics.
#[must_use]
pub fn local_from_ecef(location_m: Vector3<f64>, orientation: DisEuler) -> (Geodetic, Attitude) {
    let position = ecef_to_geodetic(location_m);
    let c_en = ned_to_ecef_rotation(position.lat_deg, position.lon_deg);
    let attitude = Attitude::from_body_to_ned(&(c_en.transpose() * orientation.body_to_ecef()));
    (position, attitude)
}

/// An ECEF velocity (or acceleration) in local NED components at `position`.
#[must_use]
pub fn ecef_vector_to_ned(position: Geodetic, v_ecef: Vector3<f64>) -> Vector3<f64> {
    ned_to_ecef_rotation(position.lat_deg, position.lon_deg).transpose() * v_ecef
}

/// The angle of the rotation taking orientation `a` to orientation `b`
/// (both body-to-ECEF matrices), radians in `[0, π]`: the single number the
/// dead-reckoning orientation threshold is compared with.
#[must_use]
pub fn rotation_angle_between(a: &Matrix3<f64>, b: &Matrix3<f64>) -> f64 {
    // acos of the trace is badly conditioned near 0; atan2 of the rotation
    // vector's sine part and the trace's cosine part is not.
    let (sin, cos) = rotation_sin_cos(a, b);
    math::atan2(sin, cos)
}

/// The rotation matrix of a rotation vector (axis × angle, radians): the
/// turn that dead reckoning applies over one interval. nalgebra's
/// `Rotation3::from_scaled_axis`, term for term (Rodrigues' formula on the
/// normalised axis), but with [`fdm_core::math`]'s sine and cosine instead
/// of the platform's, so the same on every machine. A zero vector (and only
/// that) gives the identity.
#[must_use]
pub(crate) fn rotation_from_scaled_axis(scaled_axis: Vector3<f64>) -> Matrix3<f64> {
    let angle = scaled_axis.norm();
    if angle == 0.0 {
        return Matrix3::identity();
    }
    let [ux, uy, uz] = [
        scaled_axis.x / angle,
        scaled_axis.y / angle,
        scaled_axis.z / angle,
    ];
    let (sqx, sqy, sqz) = (ux * ux, uy * uy, uz * uz);
    let (sin, cos) = math::sin_cos(angle);
    let one_m_cos = 1.0 - cos;
    Matrix3::new(
        sqx + (1.0 - sqx) * cos,
        ux * uy * one_m_cos - uz * sin,
        ux * uz * one_m_cos + uy * sin,
        ux * uy * one_m_cos + uz * sin,
        sqy + (1.0 - sqy) * cos,
        uy * uz * one_m_cos - ux * sin,
        ux * uz * one_m_cos - uy * sin,
        uy * uz * one_m_cos + ux * sin,
        sqz + (1.0 - sqz) * cos,
    )
}

/// The sine (`≥ 0`) and cosine of [`rotation_angle_between`]`(a, b)`, as
/// that function computes them before its `atan2`.
pub(crate) fn rotation_sin_cos(a: &Matrix3<f64>, b: &Matrix3<f64>) -> (f64, f64) {
    let r = a.transpose() * b;
    let cos = (r.trace() - 1.0) / 2.0;
    let sin = 0.5
        * Vector3::new(
            r[(2, 1)] - r[(1, 2)],
            r[(0, 2)] - r[(2, 0)],
            r[(1, 0)] - r[(0, 1)],
        )
        .norm();
    (sin, cos)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    #[test]
    fn rotation_from_scaled_axis_is_nalgebras_formula_with_our_sine() {
        // The same formula as nalgebra's; only the sine and cosine may differ
        // (fdm_core::math's fdlibm against the platform's libm, each under
        // 1 ulp of the true value), so entries agree within a few ulp of 1:
        // 1e-15 absolute.
        let mut seed = 0x5eed_u64;
        let mut next = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..1000 {
            let v = Vector3::new(next(), next(), next()) * 4.0;
            let ours = rotation_from_scaled_axis(v);
            let theirs = Rotation3::from_scaled_axis(v).into_inner();
            assert!((ours - theirs).amax() <= 1e-15, "{v}: {ours} vs {theirs}");
        }
        assert_eq!(
            rotation_from_scaled_axis(Vector3::zeros()),
            Matrix3::identity()
        );
        let quarter =
            rotation_from_scaled_axis(Vector3::new(0.0, 0.0, core::f64::consts::FRAC_PI_2));
        assert!((quarter * Vector3::x() - Vector3::y()).amax() <= 1e-16);
    }
}
