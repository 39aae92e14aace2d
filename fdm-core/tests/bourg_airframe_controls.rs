//! The Bourg model's data and controls: control operations as the original's
//! key handlers, the element roles, airframe validation and (de)serialisation.

use fdm_core::bourg::{
    step, Airframe, AirframeError, BourgAction, BourgAircraft, BourgControls, BourgState, Flap,
    MassProperties, Matrix3, Vector3, DELTA_THRUST_LB, MAX_THRUST_LB,
};

#[test]
fn initial_controls_and_state_are_the_originals() {
    let c = BourgControls::initial();
    assert_eq!(c.thrust_lb, 500.0);
    assert_eq!(c.rudder_deg, 0.0);
    assert!(!c.landing_flaps);
    assert_eq!(
        (c.port_aileron, c.starboard_aileron, c.elevators),
        (Flap::Neutral, Flap::Neutral, Flap::Neutral)
    );
    assert_eq!(BourgControls::default(), c);

    let s = BourgState::initial();
    assert_eq!(s.position_ft, Vector3::new(-5000.0, 0.0, 2000.0));
    assert_eq!(s.velocity_ftps, Vector3::new(60.0, 0.0, 0.0));
    assert_eq!(s.speed_ftps(), 60.0);
    assert_eq!(s.velocity_body_ftps, Vector3::zeros());
    assert_eq!(s.angular_velocity_radps, Vector3::zeros());
    assert_eq!(
        [
            s.orientation.coords.w,
            s.orientation.coords.x,
            s.orientation.coords.y,
            s.orientation.coords.z
        ],
        [1.0, 0.0, 0.0, 0.0]
    );
    assert_eq!(s.euler_angles_deg(), Vector3::zeros());
    assert!(!s.stalling);
}

#[test]
fn thrust_steps_and_clamps() {
    assert_eq!((MAX_THRUST_LB, DELTA_THRUST_LB), (3000.0, 100.0));
    let c = BourgControls::initial().apply(BourgAction::ThrustUp);
    assert_eq!(c.thrust_lb, 600.0);
    let c = c
        .apply(BourgAction::ThrustDown)
        .apply(BourgAction::ThrustDown);
    assert_eq!(c.thrust_lb, 400.0);
    let near_max = BourgControls {
        thrust_lb: 2950.0,
        ..BourgControls::initial()
    };
    assert_eq!(near_max.apply(BourgAction::ThrustUp).thrust_lb, 3000.0);
    let near_zero = BourgControls {
        thrust_lb: 50.0,
        ..BourgControls::initial()
    };
    assert_eq!(near_zero.apply(BourgAction::ThrustDown).thrust_lb, 0.0);
}

#[test]
fn surfaces_follow_the_original_key_handlers() {
    let airframe = Airframe::bourg_default();
    let flaps = |c: &BourgControls| -> Vec<i8> {
        (0..8)
            .map(|i| c.element_flap(i, &airframe.elements[i]).code())
            .collect()
    };
    let c0 = BourgControls::initial();
    assert_eq!(flaps(&c0), [0, 0, 0, 0, 0, 0, 0, 0]);
    // RollLeft: element 0 flap = 1, element 3 flap = -1; RollRight the reverse.
    assert_eq!(
        flaps(&c0.apply(BourgAction::RollLeft)),
        [1, 0, 0, -1, 0, 0, 0, 0]
    );
    assert_eq!(
        flaps(&c0.apply(BourgAction::RollRight)),
        [-1, 0, 0, 1, 0, 0, 0, 0]
    );
    // PitchUp: elements 4 and 5 flap = 1; PitchDown: -1.
    assert_eq!(
        flaps(&c0.apply(BourgAction::PitchUp)),
        [0, 0, 0, 0, 1, 1, 0, 0]
    );
    assert_eq!(
        flaps(&c0.apply(BourgAction::PitchDown)),
        [0, 0, 0, 0, -1, -1, 0, 0]
    );
    // FlapsDown: elements 1 and 2 flap = -1; FlapsUp back to 0.
    let down = c0.apply(BourgAction::FlapsDown);
    assert!(down.landing_flaps);
    assert_eq!(flaps(&down), [0, -1, -1, 0, 0, 0, 0, 0]);
    assert_eq!(flaps(&down.apply(BourgAction::FlapsUp)), [0; 8]);
    // Rudder: element 6 incidence +16 (yaw left), -16 (yaw right).
    let rudder = &airframe.elements[6];
    assert_eq!(
        c0.apply(BourgAction::YawLeft).rudder_incidence_deg(rudder),
        16.0
    );
    assert_eq!(
        c0.apply(BourgAction::YawRight).rudder_incidence_deg(rudder),
        -16.0
    );
    assert_eq!(c0.rudder_incidence_deg(rudder), 0.0);
}

#[test]
fn neutralize_keeps_thrust_and_flaps() {
    let c = BourgControls::initial()
        .apply(BourgAction::ThrustUp)
        .apply(BourgAction::FlapsDown)
        .apply(BourgAction::RollRight)
        .apply(BourgAction::PitchDown)
        .apply(BourgAction::YawLeft)
        .neutralize_surfaces();
    assert_eq!(c.thrust_lb, 600.0);
    assert!(c.landing_flaps);
    assert_eq!(c.rudder_deg, 0.0);
    assert_eq!(
        (c.port_aileron, c.starboard_aileron, c.elevators),
        (Flap::Neutral, Flap::Neutral, Flap::Neutral)
    );
}

#[test]
fn flap_codes_round_trip() {
    for flap in [Flap::TrailingEdgeDown, Flap::Neutral, Flap::TrailingEdgeUp] {
        assert_eq!(Flap::from_code(flap.code()), Some(flap));
    }
    assert_eq!(Flap::TrailingEdgeDown.code(), -1);
    assert_eq!(Flap::TrailingEdgeUp.code(), 1);
    assert_eq!(Flap::from_code(2), None);
}

#[test]
fn rigged_flaps_apply_while_the_control_is_neutral() {
    let mut airframe = Airframe::bourg_default();
    airframe.elements[4].flap = Flap::TrailingEdgeDown;
    let c = BourgControls::initial();
    assert_eq!(
        c.element_flap(4, &airframe.elements[4]),
        Flap::TrailingEdgeDown
    );
    let up = c.apply(BourgAction::PitchUp);
    assert_eq!(
        up.element_flap(4, &airframe.elements[4]),
        Flap::TrailingEdgeUp
    );
}

#[test]
fn airframe_round_trips_through_json() {
    let airframe = Airframe::bourg_default();
    assert_eq!(Airframe::default(), airframe);
    let json = serde_json::to_string_pretty(&airframe).unwrap();
    assert!(json.contains("\"flap\": \"neutral\""), "{json}");
    let back: Airframe = serde_json::from_str(&json).unwrap();
    assert_eq!(back, airframe);
    assert_eq!(back.validate(), Ok(()));
    assert_eq!(
        MassProperties::from_airframe(&back),
        *BourgAircraft::bourg_default().mass_properties()
    );
}

#[test]
fn validation_rejects_bad_airframes() {
    let mut a = Airframe::bourg_default();
    a.elements[3].design_position_ft.y = f32::NAN;
    assert_eq!(
        a.validate(),
        Err(AirframeError::NonFinite {
            element: 3,
            field: "design_position_ft.y"
        })
    );
    assert!(BourgAircraft::new(a).is_err());

    let mut a = Airframe::bourg_default();
    a.elements[7].area_ft2 = f32::INFINITY;
    assert_eq!(
        a.validate(),
        Err(AirframeError::NonFinite {
            element: 7,
            field: "area_ft2"
        })
    );

    let mut a = Airframe::bourg_default();
    for e in &mut a.elements {
        e.mass_slug = -e.mass_slug;
    }
    assert!(matches!(
        a.validate(),
        Err(AirframeError::NonPositiveMass { total_mass_slug }) if total_mass_slug < 0.0
    ));

    let mut a = Airframe::bourg_default();
    for e in &mut a.elements {
        e.mass_slug = 0.0;
    }
    assert!(matches!(
        a.validate(),
        Err(AirframeError::NonPositiveMass { .. })
    ));

    // All mass on one point on the x axis with no local inertia: Ixx = 0, so
    // the tensor is singular.
    let mut a = Airframe::bourg_default();
    for e in &mut a.elements {
        e.design_position_ft = Vector3::new(1.0, 0.0, 0.0);
        e.local_inertia = Vector3::new(0.0, 1.0, 1.0);
    }
    assert_eq!(
        a.validate(),
        Err(AirframeError::SingularInertia { determinant: 0.0 })
    );
    let message = a.validate().unwrap_err().to_string();
    assert!(message.contains("singular"), "{message}");
}

/// `Airframe::validate`'s documented checks, each bad input on its own in an
/// otherwise valid airframe: a total mass that is not finite (two finite
/// element masses whose `f32` sum overflows) is `NonPositiveMass` ("zero,
/// negative, or not finite"); an inertia tensor so large that its `f32`
/// determinant overflows is `SingularInertia` with that infinite determinant,
/// although the original's inverse (adjugate over the determinant) is then
/// finite, all zeros: not an inverse, so not "invertible with a finite
/// inverse".
#[test]
fn validation_rejects_an_infinite_total_mass_and_an_overflowing_determinant() {
    let mut a = Airframe::bourg_default();
    a.elements[0].mass_slug = 3.0e38;
    a.elements[7].mass_slug = 3.0e38;
    assert_eq!(
        a.validate(),
        Err(AirframeError::NonPositiveMass {
            total_mass_slug: f64::INFINITY
        })
    );

    // Every element 1e13 slug·ft² about each of its axes: Ixx·Iyy·Izz is
    // about 5e41, beyond f32::MAX (3.4e38).
    let mut a = Airframe::bourg_default();
    for e in &mut a.elements {
        e.local_inertia = Vector3::new(1.0e13, 1.0e13, 1.0e13);
    }
    let mass = MassProperties::from_airframe(&a);
    assert!(mass.inertia.iter().all(|v| v.is_finite()));
    assert!(
        mass.inertia_inverse.iter().all(|v| *v == 0.0),
        "the adjugate over an infinite determinant: {}",
        mass.inertia_inverse
    );
    assert_eq!(
        a.validate(),
        Err(AirframeError::SingularInertia {
            determinant: f64::INFINITY
        })
    );
    assert!(BourgAircraft::new(a).is_err());
}

/// `MassProperties::from_airframe`'s documented sums, worked by hand for an
/// airframe without Bourg's left-right symmetry (with the thesis data the
/// products of inertia Ixy and Iyz are sums that cancel to zero, whatever
/// their sign): masses 1, 3, 2, 2, 1, 3, 2, 2 slug (16 in all), design
/// positions of small integers, local inertias (k, 2k, 3k) for element
/// k − 1. First moment / mass: CG (16/16, −2/16, 7/16) ft = (1, −0.125,
/// 0.4375). The offsets `dsg − CG` are then multiples of 1/16, e.g. element 0
/// at (4, 2, 1): (3, 17/8, 9/16), so its Ixy term is 1·3·17/8. Summed:
/// Ixx = 2171/16, Iyy = 2879/16, Izz = 911/4, Ixy = 1, Ixz = −19,
/// Iyz = −265/8, in the tensor `[Ixx −Ixy −Ixz; −Ixy Iyy −Iyz; −Ixz −Iyz
/// Izz]`. Exact in `f32`: every value and partial sum is a multiple of 1/256
/// below 2^10. The inverse is the original's (adjugate / determinant), checked
/// as the inverse: the tensor times it is the identity within 1e-6, about 8
/// ulps of 1 (the inverse's entries, 1e-2 to 1e-4, each rounded to `f32`,
/// summed against entries up to 230; measured: one ulp, 1.2e-7).
#[test]
fn mass_properties_are_the_documented_sums_of_an_asymmetric_airframe() {
    let masses = [1.0, 3.0, 2.0, 2.0, 1.0, 3.0, 2.0, 2.0];
    let positions = [
        [4.0, 2.0, 1.0],
        [0.0, -3.0, 2.0],
        [2.0, 1.0, -1.0],
        [-2.0, 0.0, 3.0],
        [5.0, -1.0, 0.0],
        [1.0, 2.0, -2.0],
        [3.0, -2.0, 1.0],
        [-1.0, 1.0, 0.0],
    ];
    let mut airframe = Airframe::bourg_default();
    for (k, e) in airframe.elements.iter_mut().enumerate() {
        let n = (k + 1) as f32;
        e.mass_slug = masses[k];
        e.design_position_ft = Vector3::from(positions[k]);
        e.local_inertia = Vector3::new(n, 2.0 * n, 3.0 * n);
    }
    let aircraft = BourgAircraft::new(airframe).unwrap();
    let mass = aircraft.mass_properties();
    assert_eq!(*mass, MassProperties::from_airframe(&airframe));

    assert_eq!(mass.mass_slug, 16.0);
    assert_eq!(mass.cg_ft, Vector3::new(1.0, -0.125, 0.4375));
    let offsets = [
        [3.0, 17.0 / 8.0, 9.0 / 16.0],
        [-1.0, -23.0 / 8.0, 25.0 / 16.0],
        [1.0, 9.0 / 8.0, -23.0 / 16.0],
        [-3.0, 1.0 / 8.0, 41.0 / 16.0],
        [4.0, -7.0 / 8.0, -7.0 / 16.0],
        [0.0, 17.0 / 8.0, -39.0 / 16.0],
        [2.0, -15.0 / 8.0, 9.0 / 16.0],
        [-2.0, 9.0 / 8.0, -7.0 / 16.0],
    ];
    for (k, want) in offsets.iter().enumerate() {
        assert_eq!(mass.cg_offsets_ft[k], Vector3::from(*want), "offset {k}");
    }
    let (ixx, iyy, izz) = (2171.0 / 16.0, 2879.0 / 16.0, 911.0 / 4.0);
    let (ixy, ixz, iyz) = (1.0, -19.0, -265.0 / 8.0);
    let want = Matrix3::new(ixx, -ixy, -ixz, -ixy, iyy, -iyz, -ixz, -iyz, izz);
    assert_eq!(mass.inertia, want);

    let product = mass.inertia * mass.inertia_inverse;
    let error = (product - Matrix3::identity()).abs().max();
    assert!(error < 1e-6, "I·I⁻¹ = {product}");
}

/// `BourgAircraft::airframe` is the airframe the aircraft was built from (its
/// mass properties are that airframe's), not Bourg's default.
#[test]
fn an_aircraft_keeps_the_airframe_it_was_built_from() {
    let mut airframe = Airframe::bourg_default();
    airframe.elements[7].mass_slug = 40.0;
    airframe.elements[6].incidence_deg = 1.5;
    airframe.elements[2].flap = Flap::TrailingEdgeDown;
    let aircraft = BourgAircraft::new(airframe).unwrap();
    assert_eq!(*aircraft.airframe(), airframe);
    assert_ne!(*aircraft.airframe(), Airframe::bourg_default());
    assert_eq!(
        *BourgAircraft::bourg_default().airframe(),
        Airframe::bourg_default()
    );
}

#[test]
fn a_validated_custom_airframe_flies() {
    let mut airframe = Airframe::bourg_default();
    airframe.elements[7].mass_slug = 40.0; // heavier fuselage
    let aircraft = BourgAircraft::new(airframe).unwrap();
    assert!(aircraft.mass_properties().mass_slug > 75.0);
    let mut state = BourgState::initial();
    for _ in 0..300 {
        state = step(&aircraft, &BourgControls::initial(), &state, 1.0 / 30.0);
    }
    assert!(state.is_finite());
}

/// `BourgControls::elevator_coefficients`: with the elevators neutral and a
/// nonzero pitch trim, elements 4 and 5 fly `c + (c_deflected − c)·|trim|`,
/// trailing-edge-up tables for a positive trim, trailing-edge-down for a
/// negative one, "|trim| clamped to 1"; `BourgTerms::trim` is that factor
/// ("`|pitch_trim|` clamped to 1"). So a trim beyond ±1 (the keys never make
/// one, but the controls are public data) flies exactly as ±1, and a trim
/// inside is used as it is. Exact: the same f32 operations on the same numbers.
#[test]
fn the_pitch_trims_blend_factor_is_its_magnitude_clamped_to_one() {
    use fdm_core::bourg::airfoil::airfoil_coefficients;
    use fdm_core::bourg::BourgTerms;

    let aircraft = BourgAircraft::default();
    let elevator = aircraft.airframe().elements[4];
    let with_trim = |pitch_trim: f32| BourgControls {
        pitch_trim,
        ..BourgControls::initial()
    };
    for (trim, flap, factor) in [
        (1.75f32, Flap::TrailingEdgeUp, 1.0f32),
        (1.0, Flap::TrailingEdgeUp, 1.0),
        (0.37, Flap::TrailingEdgeUp, 0.37),
        (-0.62, Flap::TrailingEdgeDown, 0.62),
        (-1.0, Flap::TrailingEdgeDown, 1.0),
        (-3.0, Flap::TrailingEdgeDown, 1.0),
    ] {
        let controls = with_trim(trim);
        let terms = BourgTerms::new(&aircraft, &controls);
        assert_eq!(
            (terms.trim_tables, terms.trim.to_bits()),
            (flap, factor.to_bits()),
            "trim {trim}"
        );
        for angle_deg in [-7.5f32, -2.0, 0.0, 3.25, 11.0, 23.5] {
            let (c_lift, c_drag) = airfoil_coefficients(angle_deg, elevator.flap);
            let (d_lift, d_drag) = airfoil_coefficients(angle_deg, flap);
            let want = (
                c_lift + (d_lift - c_lift) * factor,
                c_drag + (d_drag - c_drag) * factor,
            );
            for index in [4, 5] {
                let got = controls.elevator_coefficients(index, &elevator, angle_deg);
                assert_eq!(
                    (got.0.to_bits(), got.1.to_bits()),
                    (want.0.to_bits(), want.1.to_bits()),
                    "trim {trim}, element {index}, {angle_deg}°"
                );
            }
        }
    }
}

/// The airfoil and rudder tables as docs/bourg-model.md ("Airfoil tables")
/// lists them (the original's `float` literals, parsed as `f32`), read back
/// through the look-ups at every angle of the table: there the documented
/// interpolation `t[i] − (a[i] − angle)·(…)` is `t[i] − 0`, the entry itself,
/// exactly. The last angle (24°) has no interval `a[i] ≤ angle < a[i+1]`: it
/// is outside (CL 0, CD 0.75), as is anything beyond either end.
#[test]
fn the_table_look_ups_give_the_documented_entries() {
    use fdm_core::bourg::airfoil::{airfoil_coefficients, rudder_coefficients};

    fn row(text: &str) -> Vec<f32> {
        text.split_whitespace()
            .map(|s| s.replace('−', "-").parse().unwrap())
            .collect()
    }
    let angles = row("−8 −4 0 4 8 12 16 20 24");
    let tables = [
        (
            Flap::Neutral,
            row("−0.54 −0.2 0.2 0.57 0.92 1.21 1.43 1.4 1.0"),
            row("0.01 0.0074 0.004 0.009 0.013 0.023 0.05 0.12 0.21"),
        ),
        (
            Flap::TrailingEdgeDown,
            row("0.0 0.45 0.85 1.02 1.39 1.65 1.75 1.38 1.17"),
            row("0.0065 0.0043 0.0055 0.0153 0.0221 0.0391 0.1 0.195 0.3"),
        ),
        (
            Flap::TrailingEdgeUp,
            row("−0.74 −0.4 0.0 0.27 0.63 0.92 1.03 1.1 0.78"),
            row("0.005 0.0043 0.0055 0.02601 0.03757 0.06647 0.13 0.18 0.25"),
        ),
    ];
    let bits = |(cl, cd): (f32, f32)| (cl.to_bits(), cd.to_bits());
    for (flap, cl, cd) in &tables {
        for i in 0..angles.len() - 1 {
            assert_eq!(
                bits(airfoil_coefficients(angles[i], *flap)),
                bits((cl[i], cd[i])),
                "{flap:?} at {}°",
                angles[i]
            );
        }
        for outside in [24.0, 24.5, -8.5, f32::NAN] {
            assert_eq!(
                bits(airfoil_coefficients(outside, *flap)),
                bits((0.0, 0.75)),
                "{flap:?} at {outside}°"
            );
        }
    }

    // The rudder: |angle| in its own table, the lift negated below 0°.
    let angles = row("0 4 8 12 16 20 24");
    let cl = row("0.16 0.456 0.736 0.968 1.144 1.12 0.8");
    let cd = row("0.0032 0.0072 0.0104 0.0184 0.04 0.096 0.168");
    for i in 0..angles.len() - 1 {
        let a = angles[i];
        assert_eq!(bits(rudder_coefficients(a)), bits((cl[i], cd[i])), "{a}°");
        if a > 0.0 {
            assert_eq!(
                bits(rudder_coefficients(-a)),
                bits((-cl[i], cd[i])),
                "-{a}°"
            );
        }
    }
    for outside in [24.0, -24.0, 30.0, f32::NAN] {
        assert_eq!(
            bits(rudder_coefficients(outside)),
            bits((0.0, 0.75)),
            "{outside}°"
        );
    }
}
