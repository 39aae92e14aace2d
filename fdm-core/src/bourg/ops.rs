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

use super::float::BourgFloat;

/// Dot product `u·v = ux vx + uy vy + uz vz`, summed left to right.
#[inline(always)]
#[must_use]
pub fn dot<F: BourgFloat>(u: &Vector3<F>, v: &Vector3<F>) -> F {
    u.x * v.x + u.y * v.y + u.z * v.z
}

/// Cross product `u^v = (uy vz − uz vy, −ux vz + uz vx, ux vy − uy vx)`.
#[inline(always)]
#[must_use]
pub fn cross<F: BourgFloat>(u: &Vector3<F>, v: &Vector3<F>) -> Vector3<F> {
    Vector3::new(
        u.y * v.z - u.z * v.y,
        -u.x * v.z + u.z * v.x,
        u.x * v.y - u.y * v.x,
    )
}

/// `Magnitude`: `sqrt(x² + y² + z²)`, the squares summed left to right.
#[inline(always)]
#[must_use]
pub fn magnitude<F: BourgFloat>(u: &Vector3<F>) -> F {
    F::sqrt(u.x * u.x + u.y * u.y + u.z * u.z)
}

/// `Normalize`: divides each component by the magnitude `m` (or by 1 if
/// `m ≤ 1e-15`), then sets any component with `|c| < 1e-15` to `+0`.
///
/// A zero vector stays zero; NaN components stay NaN.
#[inline(always)]
#[must_use]
pub fn normalize<F: BourgFloat>(u: &Vector3<F>) -> Vector3<F> {
    let mut m = magnitude(u);
    if m <= F::TOL {
        m = F::ONE;
    }
    let flush = |c: F| if F::abs(c) < F::TOL { F::ZERO } else { c };
    Vector3::new(flush(u.x / m), flush(u.y / m), flush(u.z / m))
}

/// Matrix times vector: row-wise dot products, each summed left to right.
#[inline(always)]
#[must_use]
pub fn mat_mul_vec<F: BourgFloat>(m: &Matrix3<F>, u: &Vector3<F>) -> Vector3<F> {
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
pub fn inverse<F: BourgFloat>(m: &Matrix3<F>) -> Matrix3<F> {
    let mut d = determinant(m);
    if d == F::ZERO {
        d = F::ONE;
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
pub fn determinant<F: BourgFloat>(m: &Matrix3<F>) -> F {
    let (e11, e12, e13) = (m.m11, m.m12, m.m13);
    let (e21, e22, e23) = (m.m21, m.m22, m.m23);
    let (e31, e32, e33) = (m.m31, m.m32, m.m33);
    e11 * e22 * e33 - e11 * e32 * e23 + e21 * e32 * e13 - e21 * e12 * e33 + e31 * e12 * e23
        - e31 * e22 * e13
}

/// Quaternion sum, component-wise.
#[inline(always)]
#[must_use]
pub fn quat_add<F: BourgFloat>(a: &Quaternion<F>, b: &Quaternion<F>) -> Quaternion<F> {
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
pub fn quat_scale<F: BourgFloat>(q: &Quaternion<F>, s: F) -> Quaternion<F> {
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
pub fn quat_div<F: BourgFloat>(q: &Quaternion<F>, s: F) -> Quaternion<F> {
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
pub fn conjugate<F: BourgFloat>(q: &Quaternion<F>) -> Quaternion<F> {
    Quaternion::new(q.coords.w, -q.coords.x, -q.coords.y, -q.coords.z)
}

/// Quaternion magnitude `sqrt(n² + x² + y² + z²)`, summed left to right.
#[inline(always)]
#[must_use]
pub fn quat_magnitude<F: BourgFloat>(q: &Quaternion<F>) -> F {
    F::sqrt(
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
pub fn quat_mul<F: BourgFloat>(a: &Quaternion<F>, b: &Quaternion<F>) -> Quaternion<F> {
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
pub fn quat_mul_vec<F: BourgFloat>(q: &Quaternion<F>, v: &Vector3<F>) -> Quaternion<F> {
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
pub fn qv_rotate<F: BourgFloat>(q: &Quaternion<F>, v: &Vector3<F>) -> Vector3<F> {
    let t = quat_mul(&quat_mul_vec(q, v), &conjugate(q));
    Vector3::new(t.coords.x, t.coords.y, t.coords.z)
}

/// `DegreesToRadians(d) = d * pi / 180` in `F`, left to right, with the
/// original's `pi = 3.14159265`.
#[inline(always)]
#[must_use]
pub fn degrees_to_radians<F: BourgFloat>(deg: F) -> F {
    deg * F::PI / F::DEG_180
}

/// `RadiansToDegrees(r) = r * 180 / pi` in `F`, left to right.
#[inline(always)]
#[must_use]
pub fn radians_to_degrees<F: BourgFloat>(rad: F) -> F {
    rad * F::DEG_180 / F::PI
}

/// `MakeQFromEulerAngles(roll, pitch, yaw)`, angles in degrees:
/// `euler_deg = (x roll, y pitch, z yaw)`.
///
/// Each angle is converted with [`degrees_to_radians`] in `F`, then widened to
/// `f64`; the half-angle sines and cosines and the products are `f64`, and each
/// component is rounded back to `F` (for `f32` this is the C++'s `double` mix):
/// `n = cy cp cr + sy sp sr`, `x = cy cp sr − sy sp cr`,
/// `y = cy sp cr + sy cp sr`, `z = sy cp cr − cy sp sr`.
#[must_use]
pub fn quat_from_euler_deg<F: BourgFloat>(euler_deg: &Vector3<F>) -> Quaternion<F> {
    use crate::math::{cos, sin};
    let roll = degrees_to_radians(euler_deg.x).to_f64();
    let pitch = degrees_to_radians(euler_deg.y).to_f64();
    let yaw = degrees_to_radians(euler_deg.z).to_f64();
    let (cyaw, cpitch, croll) = (cos(0.5 * yaw), cos(0.5 * pitch), cos(0.5 * roll));
    let (syaw, spitch, sroll) = (sin(0.5 * yaw), sin(0.5 * pitch), sin(0.5 * roll));
    let cyawcpitch = cyaw * cpitch;
    let syawspitch = syaw * spitch;
    let cyawspitch = cyaw * spitch;
    let syawcpitch = syaw * cpitch;
    Quaternion::new(
        F::from_f64(cyawcpitch * croll + syawspitch * sroll),
        F::from_f64(cyawcpitch * sroll - syawspitch * croll),
        F::from_f64(cyawspitch * croll + syawcpitch * sroll),
        F::from_f64(syawcpitch * croll - cyawspitch * sroll),
    )
}

/// `MakeEulerAnglesFromQ(q)`: Euler angles in degrees, `(x roll, y pitch, z yaw)`,
/// pitch positive nose-down.
///
/// The squares `n²`, `x²`, … and the inner products `xy + nz`, … are computed in
/// `F` and widened to `f64`; the rotation-matrix sums, `atan2` and `asin` are
/// `f64`; each angle is rounded to `F` and converted with
/// [`radians_to_degrees`]. If `|r31| > 0.999999` (pitch ±90°), roll is 0,
/// pitch is `−(pi/2)·r31/|r31|` and yaw `atan2(−r12, −r31·r13)`.
#[must_use]
pub fn euler_deg_from_quat<F: BourgFloat>(q: &Quaternion<F>) -> Vector3<F> {
    use crate::math::{asin, atan2};
    let (n, x, y, z) = (q.coords.w, q.coords.x, q.coords.y, q.coords.z);
    let q00 = (n * n).to_f64();
    let q11 = (x * x).to_f64();
    let q22 = (y * y).to_f64();
    let q33 = (z * z).to_f64();

    let r11 = q00 + q11 - q22 - q33;
    let r21 = (F::TWO * (x * y + n * z)).to_f64();
    let r31 = (F::TWO * (x * z - n * y)).to_f64();
    let r32 = (F::TWO * (y * z + n * x)).to_f64();
    let r33 = q00 - q11 - q22 + q33;

    let tmp = abs_f64(r31);
    if tmp > 0.999_999 {
        let r12 = (F::TWO * (x * y - n * z)).to_f64();
        let r13 = (F::TWO * (x * z + n * y)).to_f64();
        let half_pi = (-(F::PI / F::TWO)).to_f64();
        return Vector3::new(
            radians_to_degrees(F::ZERO),
            radians_to_degrees(F::from_f64(half_pi * r31 / tmp)),
            radians_to_degrees(F::from_f64(atan2(-r12, -r31 * r13))),
        );
    }

    Vector3::new(
        radians_to_degrees(F::from_f64(atan2(r32, r33))),
        radians_to_degrees(F::from_f64(asin(-r31))),
        radians_to_degrees(F::from_f64(atan2(r21, r11))),
    )
}

#[inline(always)]
fn abs_f64(x: f64) -> f64 {
    f64::from_bits(x.to_bits() & (u64::MAX >> 1))
}
