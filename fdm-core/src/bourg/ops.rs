//! The original program's vector, matrix and quaternion operations, over
//! nalgebra types, in the original's exact operation order.
//!
//! Component-wise operations (`+`, `-`, unary `-`, `* scalar`, `/ scalar` on
//! [`Vector3`]) are nalgebra's own operators: they compute each component
//! independently, exactly like the C++. Everything that sums products is written
//! out here, because nalgebra's `dot`, `cross`, `norm`, matrix product and
//! quaternion product may associate the sums differently and so round
//! differently in the last bit. Quaternion arithmetic is written out as well
//! (nalgebra's quaternion operators need `RealField`).
//!
//! Sums are evaluated left to right, as C++ does: `a + b + c` is `(a + b) + c`.
//! Rust never contracts `a * b + c` into a fused multiply-add, so there is no
//! FMA either (the reference build has none).
//!
//! Quaternions are nalgebra [`Quaternion`]s built with
//! `Quaternion::new(n, x, y, z)`: `coords.w` is the original's scalar part `n`,
//! `coords.x`, `coords.y`, `coords.z` its vector part `v`.

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::math::sqrtf;

/// π as the original writes it: `3.14159265f` (the `f32` 3.14159274).
#[allow(clippy::excessive_precision, clippy::approx_constant)]
pub const PI: f32 = 3.14159265;
/// The `Normalize` tolerance: 1e-15.
pub const TOL: f32 = 1e-15;

/// Dot product `u·v = ux vx + uy vy + uz vz`, summed left to right.
#[inline(always)]
#[must_use]
pub fn dot(u: &Vector3<f32>, v: &Vector3<f32>) -> f32 {
    u.x * v.x + u.y * v.y + u.z * v.z
}

/// Cross product `u^v = (uy vz − uz vy, −ux vz + uz vx, ux vy − uy vx)`.
#[inline(always)]
#[must_use]
pub fn cross(u: &Vector3<f32>, v: &Vector3<f32>) -> Vector3<f32> {
    Vector3::new(
        u.y * v.z - u.z * v.y,
        -u.x * v.z + u.z * v.x,
        u.x * v.y - u.y * v.x,
    )
}

/// `Magnitude`: `sqrt(x² + y² + z²)`, the squares summed left to right.
#[inline(always)]
#[must_use]
pub fn magnitude(u: &Vector3<f32>) -> f32 {
    sqrtf(u.x * u.x + u.y * u.y + u.z * u.z)
}

/// `Normalize`: divides each component by the magnitude `m` (or by 1 if
/// `m ≤ 1e-15`), then sets any component with `|c| < 1e-15` to `+0`.
///
/// A zero vector stays zero; NaN components stay NaN.
#[inline(always)]
#[must_use]
pub fn normalize(u: &Vector3<f32>) -> Vector3<f32> {
    let mut m = magnitude(u);
    if m <= TOL {
        m = 1.0;
    }
    let flush = |c: f32| if abs(c) < TOL { 0.0 } else { c };
    Vector3::new(flush(u.x / m), flush(u.y / m), flush(u.z / m))
}

/// Matrix times vector: row-wise dot products, each summed left to right.
#[inline(always)]
#[must_use]
pub fn mat_mul_vec(m: &Matrix3<f32>, u: &Vector3<f32>) -> Vector3<f32> {
    Vector3::new(
        m.m11 * u.x + m.m12 * u.y + m.m13 * u.z,
        m.m21 * u.x + m.m22 * u.y + m.m23 * u.z,
        m.m31 * u.x + m.m32 * u.y + m.m33 * u.z,
    )
}

/// The original's `Matrix3x3::Inverse`: adjugate over the determinant
/// `d = e11e22e33 − e11e32e23 + e21e32e13 − e21e12e33 + e31e12e23 − e31e22e13`
/// (evaluated left to right), with `d == 0` replaced by 1. So a singular matrix
/// yields its adjugate rather than an error.
#[inline]
#[must_use]
pub fn inverse(m: &Matrix3<f32>) -> Matrix3<f32> {
    let mut d = determinant(m);
    if d == 0.0 {
        d = 1.0;
    }
    let (e11, e12, e13) = (m.m11, m.m12, m.m13);
    let (e21, e22, e23) = (m.m21, m.m22, m.m23);
    let (e31, e32, e33) = (m.m31, m.m32, m.m33);
    Matrix3::new(
        (e22 * e33 - e23 * e32) / d,
        -(e12 * e33 - e13 * e32) / d,
        (e12 * e23 - e13 * e22) / d,
        -(e21 * e33 - e23 * e31) / d,
        (e11 * e33 - e13 * e31) / d,
        -(e11 * e23 - e13 * e21) / d,
        (e21 * e32 - e22 * e31) / d,
        -(e11 * e32 - e12 * e31) / d,
        (e11 * e22 - e12 * e21) / d,
    )
}

/// The determinant exactly as [`inverse`] computes it (before the `d == 0`
/// substitution).
#[inline]
#[must_use]
pub fn determinant(m: &Matrix3<f32>) -> f32 {
    let (e11, e12, e13) = (m.m11, m.m12, m.m13);
    let (e21, e22, e23) = (m.m21, m.m22, m.m23);
    let (e31, e32, e33) = (m.m31, m.m32, m.m33);
    e11 * e22 * e33 - e11 * e32 * e23 + e21 * e32 * e13 - e21 * e12 * e33 + e31 * e12 * e23
        - e31 * e22 * e13
}

/// Quaternion sum, component-wise.
#[inline(always)]
#[must_use]
pub fn quat_add(a: &Quaternion<f32>, b: &Quaternion<f32>) -> Quaternion<f32> {
    Quaternion::new(
        a.coords.w + b.coords.w,
        a.coords.x + b.coords.x,
        a.coords.y + b.coords.y,
        a.coords.z + b.coords.z,
    )
}

/// Quaternion times scalar, component-wise.
#[inline(always)]
#[must_use]
pub fn quat_scale(q: &Quaternion<f32>, s: f32) -> Quaternion<f32> {
    Quaternion::new(
        q.coords.w * s,
        q.coords.x * s,
        q.coords.y * s,
        q.coords.z * s,
    )
}

/// Quaternion divided by scalar, component-wise (a true division per component,
/// not a multiplication by `1/s`).
#[inline(always)]
#[must_use]
pub fn quat_div(q: &Quaternion<f32>, s: f32) -> Quaternion<f32> {
    Quaternion::new(
        q.coords.w / s,
        q.coords.x / s,
        q.coords.y / s,
        q.coords.z / s,
    )
}

/// Conjugate `~q = (n, −v)`.
#[inline(always)]
#[must_use]
pub fn conjugate(q: &Quaternion<f32>) -> Quaternion<f32> {
    Quaternion::new(q.coords.w, -q.coords.x, -q.coords.y, -q.coords.z)
}

/// Quaternion magnitude `sqrt(n² + x² + y² + z²)`, summed left to right.
#[inline(always)]
#[must_use]
pub fn quat_magnitude(q: &Quaternion<f32>) -> f32 {
    sqrtf(
        q.coords.w * q.coords.w
            + q.coords.x * q.coords.x
            + q.coords.y * q.coords.y
            + q.coords.z * q.coords.z,
    )
}

/// Quaternion product `q1*q2`, each component summed left to right:
/// `(n1n2 − x1x2 − y1y2 − z1z2, n1x2 + x1n2 + y1z2 − z1y2,
///   n1y2 + y1n2 + z1x2 − x1z2, n1z2 + z1n2 + x1y2 − y1x2)`.
#[inline(always)]
#[must_use]
pub fn quat_mul(a: &Quaternion<f32>, b: &Quaternion<f32>) -> Quaternion<f32> {
    let (n1, x1, y1, z1) = (a.coords.w, a.coords.x, a.coords.y, a.coords.z);
    let (n2, x2, y2, z2) = (b.coords.w, b.coords.x, b.coords.y, b.coords.z);
    Quaternion::new(
        n1 * n2 - x1 * x2 - y1 * y2 - z1 * z2,
        n1 * x2 + x1 * n2 + y1 * z2 - z1 * y2,
        n1 * y2 + y1 * n2 + z1 * x2 - x1 * z2,
        n1 * z2 + z1 * n2 + x1 * y2 - y1 * x2,
    )
}

/// Quaternion times vector (the vector as a pure quaternion):
/// `(−(x vx + y vy + z vz), n vx + y vz − z vy, n vy + z vx − x vz, n vz + x vy − y vx)`.
#[inline(always)]
#[must_use]
pub fn quat_mul_vec(q: &Quaternion<f32>, v: &Vector3<f32>) -> Quaternion<f32> {
    let (n, x, y, z) = (q.coords.w, q.coords.x, q.coords.y, q.coords.z);
    Quaternion::new(
        -(x * v.x + y * v.y + z * v.z),
        n * v.x + y * v.z - z * v.y,
        n * v.y + z * v.x - x * v.z,
        n * v.z + x * v.y - y * v.x,
    )
}

/// `QVRotate(q, v)`: the vector part of `(q*v)*(~q)`, i.e. `v` rotated by `q`
/// (for a unit `q`; body → earth when `q` is the orientation, earth → body with
/// its conjugate).
#[inline(always)]
#[must_use]
pub fn qv_rotate(q: &Quaternion<f32>, v: &Vector3<f32>) -> Vector3<f32> {
    let t = quat_mul(&quat_mul_vec(q, v), &conjugate(q));
    Vector3::new(t.coords.x, t.coords.y, t.coords.z)
}

/// `DegreesToRadians(d) = d * pi / 180` in `f32`, left to right, with the
/// original's `pi = 3.14159265`.
#[inline(always)]
#[must_use]
pub fn degrees_to_radians(deg: f32) -> f32 {
    deg * PI / 180.0
}

/// `RadiansToDegrees(r) = r * 180 / pi` in `f32`, left to right.
#[inline(always)]
#[must_use]
pub fn radians_to_degrees(rad: f32) -> f32 {
    rad * 180.0 / PI
}

/// `MakeQFromEulerAngles(roll, pitch, yaw)`, angles in degrees:
/// `euler_deg = (x roll, y pitch, z yaw)`.
///
/// Each angle is converted with [`degrees_to_radians`] in `f32`, then widened to
/// `f64`; the half-angle sines and cosines and the products are `f64`, and each
/// component is rounded back to `f32` (the C++'s `float`/`double` mix):
/// `n = cy cp cr + sy sp sr`, `x = cy cp sr − sy sp cr`,
/// `y = cy sp cr + sy cp sr`, `z = sy cp cr − cy sp sr`.
#[must_use]
pub fn quat_from_euler_deg(euler_deg: &Vector3<f32>) -> Quaternion<f32> {
    use crate::math::{cos, sin};
    let roll = f64::from(degrees_to_radians(euler_deg.x));
    let pitch = f64::from(degrees_to_radians(euler_deg.y));
    let yaw = f64::from(degrees_to_radians(euler_deg.z));
    let (cyaw, cpitch, croll) = (cos(0.5 * yaw), cos(0.5 * pitch), cos(0.5 * roll));
    let (syaw, spitch, sroll) = (sin(0.5 * yaw), sin(0.5 * pitch), sin(0.5 * roll));
    let cyawcpitch = cyaw * cpitch;
    let syawspitch = syaw * spitch;
    let cyawspitch = cyaw * spitch;
    let syawcpitch = syaw * cpitch;
    Quaternion::new(
        (cyawcpitch * croll + syawspitch * sroll) as f32,
        (cyawcpitch * sroll - syawspitch * croll) as f32,
        (cyawspitch * croll + syawcpitch * sroll) as f32,
        (syawcpitch * croll - cyawspitch * sroll) as f32,
    )
}

/// `MakeEulerAnglesFromQ(q)`: Euler angles in degrees, `(x roll, y pitch, z yaw)`,
/// pitch positive nose-down.
///
/// The squares `n²`, `x²`, … and the inner products `xy + nz`, … are computed in
/// `f32` and widened to `f64`; the rotation-matrix sums, `atan2` and `asin` are
/// `f64`; each angle is rounded to `f32` and converted with
/// [`radians_to_degrees`]. If `|r31| > 0.999999` (pitch ±90°), roll is 0,
/// pitch is `−(pi/2)·r31/|r31|` and yaw `atan2(−r12, −r31·r13)`.
#[must_use]
pub fn euler_deg_from_quat(q: &Quaternion<f32>) -> Vector3<f32> {
    use crate::math::{asin, atan2};
    let (n, x, y, z) = (q.coords.w, q.coords.x, q.coords.y, q.coords.z);
    let q00 = f64::from(n * n);
    let q11 = f64::from(x * x);
    let q22 = f64::from(y * y);
    let q33 = f64::from(z * z);

    let r11 = q00 + q11 - q22 - q33;
    let r21 = f64::from(2.0 * (x * y + n * z));
    let r31 = f64::from(2.0 * (x * z - n * y));
    let r32 = f64::from(2.0 * (y * z + n * x));
    let r33 = q00 - q11 - q22 + q33;

    let tmp = abs_f64(r31);
    if tmp > 0.999_999 {
        let r12 = f64::from(2.0 * (x * y - n * z));
        let r13 = f64::from(2.0 * (x * z + n * y));
        let half_pi = f64::from(-(PI / 2.0));
        return Vector3::new(
            radians_to_degrees(0.0),
            radians_to_degrees((half_pi * r31 / tmp) as f32),
            radians_to_degrees(atan2(-r12, -r31 * r13) as f32),
        );
    }

    Vector3::new(
        radians_to_degrees(atan2(r32, r33) as f32),
        radians_to_degrees(asin(-r31) as f32),
        radians_to_degrees(atan2(r21, r11) as f32),
    )
}

/// [`euler_deg_from_quat`] of every lane, bit for bit:
/// [`euler_deg_from_quat_columns`] of the quaternions' components.
#[inline(always)]
#[must_use]
pub fn euler_deg_from_quat_lanes<const N: usize>(q: &[Quaternion<f32>; N]) -> [Vector3<f32>; N] {
    let [w, x, y, z] = [0, 1, 2, 3].map(|k| -> [f32; N] {
        core::array::from_fn(|l| match k {
            0 => q[l].coords.w,
            1 => q[l].coords.x,
            2 => q[l].coords.y,
            _ => q[l].coords.z,
        })
    });
    let [roll, pitch, yaw] = euler_deg_from_quat_columns(&w, &x, &y, &z);
    core::array::from_fn(|l| Vector3::new(roll[l], pitch[l], yaw[l]))
}

/// [`euler_deg_from_quat`] of every lane `l` of the quaternion
/// `Quaternion::new(w[l], x[l], y[l], z[l])`, bit for bit, as the arrays of
/// roll, pitch and yaw (a block's lanes as they are, without a quaternion
/// or a vector per lane): the same operations, with the two `atan2` and the
/// `asin` of the lanes at once ([`crate::math::atan2_lanes`],
/// [`crate::math::asin_lanes`]); a lane at the pitch singularity
/// (`|r31| > 0.999999`) goes through [`euler_deg_from_quat`].
#[inline(always)]
#[must_use]
#[allow(clippy::cast_possible_truncation)] // as euler_deg_from_quat: f32 angles
pub fn euler_deg_from_quat_columns<const N: usize>(
    w: &[f32; N],
    x: &[f32; N],
    y: &[f32; N],
    z: &[f32; N],
) -> [[f32; N]; 3] {
    use crate::math::{asin_lanes, atan2_lanes};
    let (mut r11, mut r21, mut r31, mut r32, mut r33) =
        ([0.0; N], [0.0; N], [0.0; N], [0.0; N], [0.0; N]);
    for l in 0..N {
        let (n, x, y, z) = (w[l], x[l], y[l], z[l]);
        let q00 = f64::from(n * n);
        let q11 = f64::from(x * x);
        let q22 = f64::from(y * y);
        let q33 = f64::from(z * z);
        r11[l] = q00 + q11 - q22 - q33;
        r21[l] = f64::from(2.0 * (x * y + n * z));
        r31[l] = f64::from(2.0 * (x * z - n * y));
        r32[l] = f64::from(2.0 * (y * z + n * x));
        r33[l] = q00 - q11 - q22 + q33;
    }
    let roll = atan2_lanes(r32, r33);
    let yaw = atan2_lanes(r21, r11);
    let pitch = asin_lanes(r31.map(|r| -r));
    let mut out = [
        roll.map(|r| radians_to_degrees(r as f32)),
        pitch.map(|p| radians_to_degrees(p as f32)),
        yaw.map(|y| radians_to_degrees(y as f32)),
    ];
    for l in 0..N {
        if abs_f64(r31[l]) > 0.999_999 {
            let e = euler_deg_from_quat(&Quaternion::new(w[l], x[l], y[l], z[l]));
            (out[0][l], out[1][l], out[2][l]) = (e.x, e.y, e.z);
        }
    }
    out
}

#[inline(always)]
fn abs_f64(x: f64) -> f64 {
    f64::from_bits(x.to_bits() & (u64::MAX >> 1))
}

/// `fabsf`: clears the sign bit (also of −0 and NaN).
#[inline(always)]
pub(crate) fn abs(x: f32) -> f32 {
    f32::from_bits(x.to_bits() & 0x7fff_ffff)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lane Euler angles are [`euler_deg_from_quat`] bit for bit: random
    /// orientations (unit quaternions of every attitude, and unnormalised
    /// ones), orientations at and near the pitch singularity (the scalar
    /// path), and special components (zero, NaN, infinity) in one lane.
    #[test]
    fn euler_lanes_are_euler_deg_from_quat() {
        let check = |q: [Quaternion<f32>; 16]| {
            let lanes = euler_deg_from_quat_lanes(&q);
            for (l, got) in lanes.iter().enumerate() {
                let want = euler_deg_from_quat(&q[l]);
                for k in 0..3 {
                    assert!(
                        got[k].to_bits() == want[k].to_bits()
                            || (got[k].is_nan() && want[k].is_nan()),
                        "{:?}: lanes {got:?}, scalar {want:?}",
                        q[l]
                    );
                }
            }
        };
        let mut bits = crate::math::test_bits(0xe01e_7a11);
        #[allow(clippy::cast_precision_loss, clippy::cast_possible_truncation)]
        let mut unit = move || ((bits() >> 11) as f64 / (1_u64 << 53) as f64) as f32;
        let mut random = |normalise: bool| {
            let mut q = Quaternion::new(
                unit() * 2.0 - 1.0,
                unit() * 2.0 - 1.0,
                unit() * 2.0 - 1.0,
                unit() * 2.0 - 1.0,
            );
            if normalise {
                let m = sqrtf(q.coords.norm_squared());
                q = Quaternion::new(q.w / m, q.i / m, q.j / m, q.k / m);
            }
            q
        };
        for _ in 0..100_000 {
            check(core::array::from_fn(|_| random(true)));
            check(core::array::from_fn(|_| random(false)));
        }
        // Attitudes of flight (pitch within ±29°, so every lane's `asin`
        // below 0.5: the lane `asin`'s shortcut), and the same with one lane
        // pitched past 30° (both of its paths).
        let mut flight_bits = crate::math::test_bits(0xf1_1e5);
        #[allow(clippy::cast_precision_loss, clippy::cast_possible_truncation)]
        let mut unit = move || ((flight_bits() >> 11) as f64 / (1_u64 << 53) as f64) as f32;
        for steep in [None, Some(40.0), Some(-75.0)] {
            for l in 0..2_000 {
                let mut q: [Quaternion<f32>; 16] = core::array::from_fn(|_| {
                    let (roll, pitch, yaw) =
                        (unit() * 360.0 - 180.0, unit() * 58.0 - 29.0, unit() * 360.0);
                    quat_from_euler_deg(&Vector3::new(roll, pitch, yaw))
                });
                if let Some(p) = steep {
                    q[l % 16] = quat_from_euler_deg(&Vector3::new(10.0, p + unit(), 30.0));
                }
                check(q);
            }
        }
        // Pitch ±90 degrees and near it (r31 about ±1).
        for pitch in [89.9, 89.99, 89.999, 90.0, -90.0, -89.95, 45.0] {
            for l in 0..16 {
                let mut q: [Quaternion<f32>; 16] = core::array::from_fn(|_| random(true));
                q[l] = quat_from_euler_deg(&Vector3::new(10.0, pitch, 30.0));
                check(q);
            }
        }
        for odd in [0.0, -0.0, f32::NAN, f32::INFINITY, 1e-30, 1e30] {
            for l in 0..16 {
                let mut q: [Quaternion<f32>; 16] = core::array::from_fn(|_| random(true));
                q[l].coords.y = odd;
                check(q);
                q[l] = Quaternion::new(odd, 0.0, 0.0, 0.0);
                check(q);
            }
        }
    }
}
