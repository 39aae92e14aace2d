//! Every row of `reference/bourg_math.md` (the original's vector, matrix and
//! quaternion operations on fixed inputs, with their exact f32 outputs from the
//! C++ built with g++ and glibc), through the functions the model really uses:
//! nalgebra's component-wise operators for `+`, `-`, negation, `* s` and `/ s`
//! on vectors, and `fdm_core::bourg::ops` for everything else.
//!
//! Every row is compared for exact `f32` bit equality (sign of zero included).
//! Also: the mass properties of Bourg's airframe against the numbers docs/bourg-model.md
//! prints (9 significant digits, i.e. exact f32 values), and the airfoil
//! tables at their edges.

use fdm_core::bourg::ops::{
    conjugate, cross, determinant, dot, euler_deg_from_quat, inverse, magnitude, mat_mul_vec,
    normalize, quat_add, quat_div, quat_from_euler_deg, quat_magnitude, quat_mul, quat_mul_vec,
    quat_scale, qv_rotate,
};
use fdm_core::bourg::{
    drag_coefficient, lift_coefficient, rudder_drag_coefficient, rudder_lift_coefficient, Airframe,
    Flap, MassProperties,
};
use fdm_core::bourg::{Matrix3, Quaternion, Vector3};

/// Parses a decimal as the nearest f32 (the reference's decimals are exact f32
/// values or round to them).
fn f(s: &str) -> f32 {
    s.trim().parse().unwrap_or_else(|e| panic!("{s}: {e}"))
}

fn v(x: &str, y: &str, z: &str) -> Vector3<f32> {
    Vector3::new(f(x), f(y), f(z))
}

/// A quaternion `(n, x, y, z)`.
fn q(n: &str, x: &str, y: &str, z: &str) -> Quaternion<f32> {
    Quaternion::new(f(n), f(x), f(y), f(z))
}

fn m(rows: [[&str; 3]; 3]) -> Matrix3<f32> {
    Matrix3::from_fn(|r, c| f(rows[r][c]))
}

#[track_caller]
fn same(got: f32, want: f32, what: &str) {
    assert_eq!(
        got.to_bits(),
        want.to_bits(),
        "{what}: got {got:e}, expected {want:e}"
    );
}

#[track_caller]
fn same_v(got: &Vector3<f32>, want: &Vector3<f32>, what: &str) {
    for i in 0..3 {
        same(got[i], want[i], &format!("{what} [{i}]"));
    }
}

#[track_caller]
fn same_q(got: &Quaternion<f32>, want: &Quaternion<f32>, what: &str) {
    let g = [got.coords.w, got.coords.x, got.coords.y, got.coords.z];
    let w = [want.coords.w, want.coords.x, want.coords.y, want.coords.z];
    for i in 0..4 {
        same(g[i], w[i], &format!("{what} (n,x,y,z)[{i}]"));
    }
}

#[track_caller]
fn same_m(got: &Matrix3<f32>, want: &Matrix3<f32>, what: &str) {
    for r in 0..3 {
        for c in 0..3 {
            same(
                got[(r, c)],
                want[(r, c)],
                &format!("{what} e{}{}", r + 1, c + 1),
            );
        }
    }
}

fn q_a() -> Quaternion<f32> {
    q("0.99817944", "-0.022753572", "-0.039973494", "0.03901701")
}

fn q_b() -> Quaternion<f32> {
    q("0.3199454", "0.04186167", "-0.2620119", "-0.9095231")
}

fn inertia() -> Matrix3<f32> {
    m([
        ["2549.629150390625", "-0", "166.91925048828125"],
        ["-0", "2024.4990234375", "-0"],
        ["166.91925048828125", "-0", "4414.73388671875"],
    ])
}

// ---------------------------------------------------------------- Vector

#[test]
fn vector_magnitude() {
    same(
        magnitude(&v("1", "1", "1")),
        f("1.73205077648162841796875"),
        "|(1,1,1)|",
    );
    same(
        magnitude(&v("1", "2", "3")),
        f("3.7416574954986572265625"),
        "|(1,2,3)|",
    );
    let u = v(
        "63.73516082763671875",
        "-0.004545502364635467529296875",
        "-8.11302661895751953125",
    );
    same(magnitude(&u), f("64.24945068359375"), "|u|");
}

#[test]
fn vector_normalize() {
    let third = f("0.57735025882720947265625");
    same_v(
        &normalize(&v("1", "1", "1")),
        &Vector3::new(third, third, third),
        "(1,1,1)",
    );
    let third3 = f("0.577350318431854248046875");
    same_v(
        &normalize(&v("3", "3", "3")),
        &Vector3::new(third3, third3, third3),
        "(3,3,3)",
    );
    same_v(
        &normalize(&v("1", "2", "3")),
        &v(
            "0.267261236906051635742188",
            "0.534522473812103271484375",
            "0.80178368091583251953125",
        ),
        "(1,2,3)",
    );
    same_v(
        &normalize(&v(
            "-0.061048544943332672119140625",
            "0",
            "0.998134791851043701171875",
        )),
        &v(
            "-0.0610485486686229705810546875",
            "0",
            "0.9981348514556884765625",
        ),
        "wing normal",
    );
}

#[test]
fn vector_componentwise_operators() {
    same_v(&-v("1", "2", "3"), &v("-1", "-2", "-3"), "negate");
    same_v(
        &(v("10", "20", "30") + v("1", "2", "3")),
        &v("11", "22", "33"),
        "add",
    );
    let a = v(
        "0.000291615608148276805877685546875",
        "-0.001196154276840388774871826171875",
        "0.0007719345740042626857757568359375",
    );
    let b = v(
        "0.0000101931509561836719512939453125",
        "-0.005297116935253143310546875",
        "0.000000784755684435367584228515625",
    );
    same_v(
        &(a + b),
        &v(
            "0.000301808759104460477828979",
            "-0.00649327132850885391235352",
            "0.000772719329688698053359985",
        ),
        "add u+v",
    );
    same_v(
        &(v("10", "20", "30") - v("1", "2", "3")),
        &v("9", "18", "27"),
        "sub",
    );
    // The row is labelled "v − u", but its numbers are the first vector of the
    // add row minus the second (x: 2.9162e-4 − 1.0193e-5 = 2.8142e-4 > 0).
    same_v(
        &(a - b),
        &v(
            "0.000281422457192093133926392",
            "0.00410096254199743270874023",
            "0.000771149818319827318191528",
        ),
        "sub (first - second)",
    );
    same_v(&(v("1", "2", "3") * 3.0), &v("3", "6", "9"), "x scalar");
    same_v(
        &(v("1", "2", "3") / 3.0),
        &v(
            "0.333333343267440795898438",
            "0.666666686534881591796875",
            "1",
        ),
        "/ scalar",
    );
}

#[test]
fn vector_cross_and_dot() {
    same_v(
        &cross(&v("1", "0", "0"), &v("0", "1", "1")),
        &v("0", "-1", "1"),
        "cross",
    );
    let u = v(
        "1.01931509561836719512939453125e-05",
        "-0.005297116935253143310546875",
        "7.84755684435367584228515625e-07",
    );
    let w = v("1.81550502777099609375", "0", "-0.6772263050079345703125");
    same_v(
        &cross(&u, &w),
        &v(
            "0.0035873469896614551544189453125",
            "8.327797331730835139751434326171875e-06",
            "0.009616942144930362701416015625",
        ),
        "cross (fuselage offset)",
    );
    same(dot(&v("10", "20", "30"), &v("1", "2", "3")), 140.0, "dot");
    let drag = v(
        "-0.9932043552398681640625",
        "-3.16645900966250337660312652587890625e-06",
        "0.116383351385593414306640625",
    );
    same(
        dot(&drag, &v("0", "0", "1")),
        f("0.116383351385593414306640625"),
        "dot drag·normal",
    );
}

// ---------------------------------------------------------------- Matrix

#[test]
fn matrix_inverse() {
    let singular = m([["1", "2", "3"], ["4", "5", "6"], ["7", "8", "9"]]);
    same_m(
        &inverse(&singular),
        &m([["-3", "6", "-3"], ["6", "-12", "6"], ["-3", "6", "-3"]]),
        "inverse of a singular matrix (d = 1)",
    );
    same_m(
        &inverse(&inertia()),
        &m([
            [
                "0.0003931871615350246429443359375",
                "-0",
                "-1.48662438732571899890899658203125e-05",
            ],
            ["-0", "0.0004939493373967707157135009765625", "-0"],
            [
                "-1.48662438732571899890899658203125e-05",
                "-0",
                "0.0002270762925036251544952392578125",
            ],
        ]),
        "inverse of the inertia",
    );
}

#[test]
fn matrix_times_vector() {
    let m19 = m([["1", "2", "3"], ["4", "5", "6"], ["7", "8", "9"]]);
    same_v(
        &mat_mul_vec(&m19, &v("3", "3", "3")),
        &v("18", "45", "72"),
        "M·v",
    );
    let omega = v(
        "0.000029893242754042148590087890625",
        "0.063622482120990753173828125",
        "-0.000000184518285095691680908203125",
    );
    same_v(
        &mat_mul_vec(&inertia(), &omega),
        &v(
            "0.076185882091522216796875",
            "128.80364990234375",
            "0.00417515868321061134338379",
        ),
        "inertia·ω",
    );
}

// ---------------------------------------------------------------- Quaternion

#[test]
fn quaternion_magnitude() {
    same(quat_magnitude(&q("2", "2", "2", "2")), 4.0, "|(2,2,2,2)|");
    same(
        quat_magnitude(&q("8.1", "15.25", "0.1", "2.89")),
        f("17.5081310272216796875"),
        "|(8.1,15.25,0.1,2.89)|",
    );
}

#[test]
fn quaternion_componentwise_operations() {
    same_q(
        &quat_add(&q("2", "1", "2", "3"), &q("3", "1", "2", "3")),
        &q("5", "2", "4", "6"),
        "add",
    );
    same_q(
        &quat_add(
            &q_a(),
            &q("0.20345166", "-0.35279512", "-0.034243274", "-0.91267216"),
        ),
        &q(
            "1.201631069183349609375",
            "-0.375548690557479858398438",
            "-0.0742167681455612182617188",
            "-0.873655140399932861328125",
        ),
        "add qA",
    );
    same_q(
        &quat_scale(&q("2", "1", "2", "3"), 3.0),
        &q("6", "3", "6", "9"),
        "x scalar",
    );
    same_q(
        &quat_scale(&q_a(), f("0.016666668")),
        &q(
            "0.0166363250464200973510742",
            "-0.000379226228687912225723267",
            "-0.000666224921587854623794556",
            "0.00065028353128582239151001",
        ),
        "qA x scalar",
    );
    same_q(
        &quat_div(&q("2", "1", "2", "3"), 3.0),
        &q(
            "0.666666686534881591796875",
            "0.333333343267440795898438",
            "0.666666686534881591796875",
            "1",
        ),
        "/ scalar",
    );
    same_q(
        &quat_div(&q_a(), f("0.016666668")),
        &q(
            "59.8907623291015625",
            "-1.36521422863006591796875",
            "-2.3984096050262451171875",
            "2.3410205841064453125",
        ),
        "qA / scalar",
    );
    same_q(
        &conjugate(&q("2", "1", "2", "3")),
        &q("2", "-1", "-2", "-3"),
        "conjugate",
    );
    same_q(
        &conjugate(&q_b()),
        &q(
            "0.319945394992828369140625",
            "-0.0418616682291030883789062",
            "0.26201188564300537109375",
            "0.90952312946319580078125",
        ),
        "conjugate qB",
    );
}

#[test]
fn quaternion_products_and_rotation() {
    same_q(
        &quat_mul(&q("2", "1", "2", "3"), &q("3", "1", "2", "3")),
        &q("-8", "5", "10", "15"),
        "q·q",
    );
    same_q(
        &quat_mul(&q_a(), &q_b()),
        &q(
            "0.345328778028488159179688",
            "0.0810852870345115661621094",
            "-0.293385803699493408203125",
            "-0.8877489566802978515625",
        ),
        "qA·qB",
    );
    same_q(
        &quat_mul_vec(&q("2", "1", "2", "3"), &v("3", "1", "2")),
        &q("-11", "7", "9", "-1"),
        "q·v",
    );
    let force = v("127.105736", "-13.1427", "-10.31398");
    same_q(
        &quat_mul_vec(&q_a(), &force),
        &q(
            "2.7691707611083984375",
            "127.79940032958984375",
            "-8.39416790008544921875",
            "-4.91529941558837890625",
        ),
        "qA·v",
    );
    same_v(
        &qv_rotate(&q("2", "1", "2", "3"), &v("3", "1", "2")),
        &v("-4", "62", "26"),
        "QVRotate",
    );
    same_v(
        &qv_rotate(&q_a(), &force),
        &v(
            "128.1537475585937",
            "-3.393682956695556640625",
            "0.285190761089324951171875",
        ),
        "QVRotate qA",
    );
}

#[test]
fn quaternion_from_euler_angles() {
    same_q(
        &quat_from_euler_deg(&v("5", "7", "10")),
        &q(
            "0.993622303009033203125",
            "0.0380566865205764770507812",
            "0.0645529404282569885253906",
            "0.0842576175928115844726562",
        ),
        "(5,7,10)",
    );
    same_q(
        &quat_from_euler_deg(&v(
            "-2.790951251983642578125",
            "-4.475101947784423828125",
            "4.585966587066650390625",
        )),
        &q(
            "0.998179376125335693359375",
            "-0.0227535702288150787353516",
            "-0.0399734899401664733886719",
            "0.0390170104801654815673828",
        ),
        "Euler of qA",
    );
}

#[test]
fn euler_angles_from_quaternion() {
    same_v(
        &euler_deg_from_quat(&q("2", "1", "2", "3")),
        &v("0", "90", "15.9453945159912109375"),
        "(2,1,2,3), gimbal branch",
    );
    same_v(
        &euler_deg_from_quat(&q_a()),
        &v(
            "-2.790951251983642578125",
            "-4.475101947784423828125",
            "4.585966587066650390625",
        ),
        "qA",
    );
    same_v(
        &euler_deg_from_quat(&q_b()),
        &v(
            "30.3658618927001953125",
            "-5.25052165985107421875",
            "-142.664825439453125",
        ),
        "qB",
    );
    same_v(
        &euler_deg_from_quat(&q(
            "0.20345166",
            "-0.35279512",
            "-0.034243274",
            "-0.91267216",
        )),
        &v(
            "-6.178070545196533203125",
            "-41.140392303466796875",
            "-152.5458831787109375",
        ),
        "(0.20345166,...)",
    );
}

// ---------------------------------------------------------------- Mass properties

#[test]
fn mass_properties_match_the_spec() {
    let mass = MassProperties::from_airframe(&Airframe::bourg_default());
    same(mass.mass_slug, f("67.7099991"), "total mass");
    same_v(&mass.cg_ft, &v("13.434495", "0", "2.17722631"), "CG");
    same_m(
        &mass.inertia,
        &m([
            ["2549.62915", "-0", "166.91925"],
            ["-0", "2024.49902", "-0"],
            ["166.91925", "-0", "4414.73389"],
        ]),
        "inertia",
    );
    same_m(
        &mass.inertia_inverse,
        &m([
            ["0.000393187162", "-0", "-1.48662439e-05"],
            ["-0", "0.000493949337", "-0"],
            ["-1.48662439e-05", "-0", "0.000227076293"],
        ]),
        "inertia inverse",
    );
    let offsets = [
        ("1.06550503", "12", "0.322773695"),
        ("1.06550503", "5.5", "0.322773695"),
        ("1.06550503", "-5.5", "0.322773695"),
        ("1.06550503", "-12", "0.322773695"),
        ("-10.4044952", "2.5", "0.822773695"),
        ("-10.4044952", "-2.5", "0.822773695"),
        ("-11.184495", "0", "2.82277369"),
        ("1.81550503", "0", "-0.677226305"),
    ];
    for (i, (x, y, z)) in offsets.iter().enumerate() {
        same_v(
            &mass.cg_offsets_ft[i],
            &v(x, y, z),
            &format!("cg offset {i}"),
        );
    }
    let wing = v("-0.0610485487", "0", "0.998134851");
    let flat = v("0", "0", "1");
    let fin = v("0", "1", "-4.37113883e-08");
    let normals = [wing, wing, wing, wing, flat, flat, fin, flat];
    for (i, want) in normals.iter().enumerate() {
        same_v(&mass.normals[i], want, &format!("normal {i}"));
    }
}

// ---------------------------------------------------------------- Airfoil tables

#[test]
fn airfoil_tables_at_their_edges() {
    // Table points and the out-of-table values of docs/bourg-model.md.
    same(lift_coefficient(0.0f32, Flap::Neutral), 0.2, "CL(0)");
    same(
        lift_coefficient(-8.0f32, Flap::TrailingEdgeDown),
        0.0,
        "CL fd(-8)",
    );
    same(
        lift_coefficient(4.0f32, Flap::TrailingEdgeUp),
        0.27,
        "CL fu(4)",
    );
    same(
        lift_coefficient(2.0f32, Flap::Neutral),
        0.385,
        "CL(2), halfway",
    );
    same(
        lift_coefficient(24.0f32, Flap::Neutral),
        0.0,
        "CL(24): outside",
    );
    same(
        lift_coefficient(-8.5f32, Flap::Neutral),
        0.0,
        "CL(-8.5): outside",
    );
    same(lift_coefficient(f32::NAN, Flap::Neutral), 0.0, "CL(NaN)");
    same(drag_coefficient(0.0f32, Flap::Neutral), 0.004, "CD(0)");
    same(
        drag_coefficient(8.0f32, Flap::TrailingEdgeUp),
        0.03757,
        "CD fu(8)",
    );
    same(drag_coefficient(30.0f32, Flap::Neutral), 0.75, "CD outside");
    same(drag_coefficient(f32::NAN, Flap::Neutral), 0.75, "CD(NaN)");
    // The rudder's discontinuity at 0 degrees.
    same(rudder_lift_coefficient(0.0f32), 0.16, "rudder CL(+0)");
    same(rudder_lift_coefficient(-0.0f32), 0.16, "rudder CL(-0)");
    same(rudder_lift_coefficient(-1e-7f32), -0.16, "rudder CL(-1e-7)");
    same(rudder_lift_coefficient(-16.0f32), -1.144, "rudder CL(-16)");
    same(rudder_lift_coefficient(24.0f32), 0.0, "rudder CL outside");
    same(rudder_drag_coefficient(-4.0f32), 0.0072, "rudder CD(-4)");
    same(rudder_drag_coefficient(25.0f32), 0.75, "rudder CD outside");
}

#[test]
fn the_generic_quaternion_operations_give_the_same_rows() {
    // The step's own quaternion type (`Q4`, `bourg/generic.rs`, written once
    // for one aircraft and for lanes) on the rows above: the same bits. The
    // step reads only the vector part of `(q·v)·~q`, so the scalar part of
    // `product` is checked here, from the reference rows.
    use fdm_core::bourg::Q4;
    let g = |a: Quaternion<f32>| Q4::<f32>::from(a);
    let back = |a: Q4<f32>| Quaternion::<f32>::from(a);
    same_q(
        &back(g(q("2", "1", "2", "3")).product(g(q("3", "1", "2", "3")))),
        &q("-8", "5", "10", "15"),
        "Q4 q·q",
    );
    same_q(
        &back(g(q_a()).product(g(q_b()))),
        &quat_mul(&q_a(), &q_b()),
        "Q4 qA·qB",
    );
    same_q(
        &back(g(q_b()).product(g(q_a()))),
        &quat_mul(&q_b(), &q_a()),
        "Q4 qB·qA",
    );
    let force = v("127.105736", "-13.1427", "-10.31398");
    same_q(
        &back(g(q_a()).mul_vec(force.into())),
        &quat_mul_vec(&q_a(), &force),
        "Q4 qA·v",
    );
    same_q(&back(g(q_a()).conjugate()), &conjugate(&q_a()), "Q4 ~qA");
    same_v(
        &g(q_a()).rotate(force.into()).into(),
        &qv_rotate(&q_a(), &force),
        "Q4 QVRotate qA",
    );
    same(g(q_a()).magnitude(), quat_magnitude(&q_a()), "Q4 |qA|");
}

#[test]
fn normalize_at_its_tolerance() {
    // docs/bourg-model.md, "Normalize": divide by the magnitude (by 1 if it
    // is <= tol), then flush to +0 any component with |c| < tol, tol = 1e-15
    // (f32). No reference row reaches either comparison at its edge. Exact:
    // a magnitude of one nonzero component is that component (`sqrtf(x*x)`
    // is |x| when x*x neither overflows nor underflows), and dividing by 1
    // changes nothing.
    let tol = 1e-15_f32;
    let zero = v("0", "0", "0");
    // Magnitude exactly tol: divided by 1, so the component stays tol, which
    // is not below tol: kept (a vector at the tolerance is not made unit).
    same_v(
        &normalize(&Vector3::new(tol, 0.0, 0.0)),
        &Vector3::new(tol, 0.0, 0.0),
        "(tol,0,0)",
    );
    same_v(
        &normalize(&Vector3::new(0.0, -tol, 0.0)),
        &Vector3::new(0.0, -tol, 0.0),
        "(0,-tol,0)",
    );
    // Just above tol: a unit vector.
    let above = f32::from_bits(tol.to_bits() + 1);
    same_v(
        &normalize(&Vector3::new(0.0, 0.0, above)),
        &v("0", "0", "1"),
        "(0,0,tol+)",
    );
    // Below tol: divided by 1, then the component is below tol: +0, of
    // either sign.
    let below = f32::from_bits(tol.to_bits() - 1);
    same_v(
        &normalize(&Vector3::new(-below, 0.0, 0.0)),
        &zero,
        "(-tol-,0,0)",
    );
    same_v(
        &normalize(&Vector3::new(0.0, 0.0, below)),
        &zero,
        "(0,0,tol-)",
    );
    // A unit vector's components below tol are flushed to +0 (a negative one
    // too), those at or above it kept.
    same_v(
        &normalize(&Vector3::new(1.0, -1e-16, 1e-20)),
        &v("1", "0", "0"),
        "(1,-1e-16,1e-20)",
    );
    same_v(
        &normalize(&Vector3::new(1.0, tol, -tol)),
        &Vector3::new(1.0, tol, -tol),
        "(1,tol,-tol)",
    );
}

#[test]
fn cross_and_dot_of_general_vectors() {
    // docs/bourg-model.md, "Cross: (uy·vz − uz·vy, −ux·vz + uz·vx,
    // ux·vy − uy·vx)", "Dot: ux·vx + uy·vy + uz·vz". The reference rows have
    // a zero in one vector, so some terms never show; small integers give
    // every product and difference exactly (hand-worked):
    // (1, 2, 3) × (4, 5, 6) = (12 − 15, −6 + 12, 5 − 8) = (−3, 6, −3).
    let (a, b) = (v("1", "2", "3"), v("4", "5", "6"));
    same_v(&cross(&a, &b), &v("-3", "6", "-3"), "(1,2,3)x(4,5,6)");
    same_v(&cross(&b, &a), &v("3", "-6", "3"), "(4,5,6)x(1,2,3)");
    // (2, −3, 5) × (−7, 11, 13) = (−39 − 55, −26 − 35, 22 − 21) = (−94, −61, 1).
    same_v(
        &cross(&v("2", "-3", "5"), &v("-7", "11", "13")),
        &v("-94", "-61", "1"),
        "(2,-3,5)x(-7,11,13)",
    );
    // 1·4 + 2·5 + 3·6 = 32; 2·(−7) − 3·11 + 5·13 = 18.
    same(dot(&a, &b), 32.0, "(1,2,3).(4,5,6)");
    same(
        dot(&v("2", "-3", "5"), &v("-7", "11", "13")),
        18.0,
        "(2,-3,5).(-7,11,13)",
    );
}

#[test]
fn inverse_of_a_general_matrix() {
    // docs/bourg-model.md, "Inverse: the adjugate divided by d" with
    // `d = e11·e22·e33 − e11·e32·e23 + e21·e32·e13 − e21·e12·e33 +
    // e31·e12·e23 − e31·e22·e13`. The reference rows are a singular matrix
    // (d replaced by 1) and the inertia, whose four products Ixy, Iyz are
    // zero: neither shows every entry divided by a d other than 1. Worked by
    // hand on small integers: d = 4 (below), adjugate [[12, 24, 4],
    // [−7, −15, −2], [−3, −7, −2]] (M · adj = 4·I), so every product and the
    // inverse are exact in f32 (quarters).
    let m3 = m([["4", "5", "3"], ["-2", "-3", "-1"], ["1", "3", "-3"]]);
    // 4·(−3)·(−3) − 4·3·(−1) + (−2)·3·3 − (−2)·5·(−3) + 1·5·(−1) − 1·(−3)·3
    // = 36 + 12 − 18 − 30 − 5 + 9 = 4.
    same(determinant(&m3), 4.0, "det");
    same_m(
        &inverse(&m3),
        &m([
            ["3", "6", "1"],
            ["-1.75", "-3.75", "-0.5"],
            ["-0.75", "-1.75", "-0.5"],
        ]),
        "inverse",
    );
}

#[test]
fn euler_angles_at_the_gimbal_lock_keep_the_heading() {
    // docs/bourg-model.md, "Quaternion → Euler angles": if |r31| > 0.999999
    // (pitch at ±90°), roll = 0, pitch = −(pi/2)·r31/|r31| and yaw =
    // atan2(−r12, −r31·r13), with the rotation matrix's r12 = 2(xy − nz),
    // r13 = 2(xz + ny) (the same matrix as r21 = 2(xy + nz), r31 =
    // 2(xz − ny)). So a quaternion made from (roll 0, pitch ±90°, yaw ψ)
    // comes back as (0, ±90, ψ): the reference row of this branch,
    // (2, 1, 2, 3), has n·y = n + y and cannot tell r13's product from a sum.
    // Pitch and roll exactly (the branch's own constants); the yaw within
    // 1e-4°: the quaternion's f32 components carry about 6e-8 relative
    // error into r12 and r13, some 1e-5° at most in the angle.
    for (pitch, yaw) in [(90.0, 30.0), (90.0, -135.0), (-90.0, -120.0), (-90.0, 60.0)] {
        let q = quat_from_euler_deg(&Vector3::new(0.0, pitch, yaw));
        let e = euler_deg_from_quat(&q);
        same(e.x, 0.0, "roll");
        same(e.y, pitch, "pitch");
        assert!(
            (e.z - yaw).abs() < 1e-4,
            "pitch {pitch}, yaw {yaw}: got {e:?}"
        );
    }
}
