//! The Entity State PDU bytes, read back field by field with plain
//! big-endian reads at the offsets of IEEE 1278.1 (header 12 bytes, then
//! entity id 6, force 1, variable-parameter count 1, entity type 8,
//! alternative type 8, velocity 12, location 24, orientation 12,
//! appearance 4, dead-reckoning parameters 40, marking 12, capabilities 4 =
//! 144 bytes), independently of dis-rs's parser; and the dis-rs round trip.
//! All comparisons are exact: the wire values are the `f32`/`f64` we put in.

use bytes::BytesMut;
use fdm_dis::dis_rs::enumerations::ForceId;
use fdm_dis::dis_rs::model::PduBody;
use fdm_dis::geodesy::{Attitude, Geodetic};
use fdm_dis::{
    dis_timestamp, encode_entity_state, AircraftKind, AircraftState, DisOutputError, DisVersion,
    DrAlgorithm, EntityConfig, EntityIdentity, Marking, WireState,
};
use nalgebra::Vector3;

fn u16_at(b: &[u8], o: usize) -> u16 {
    u16::from_be_bytes([b[o], b[o + 1]])
}
fn u32_at(b: &[u8], o: usize) -> u32 {
    u32::from_be_bytes(b[o..o + 4].try_into().unwrap())
}
fn f32_at(b: &[u8], o: usize) -> f32 {
    f32::from_be_bytes(b[o..o + 4].try_into().unwrap())
}
fn f64_at(b: &[u8], o: usize) -> f64 {
    f64::from_be_bytes(b[o..o + 8].try_into().unwrap())
}

fn sample_state() -> AircraftState {
    let mut s = AircraftState::new(
        1800.0,
        Geodetic {
            lat_deg: 39.8264,
            lon_deg: -84.0483,
            alt_m: 1251.5,
        },
        Attitude {
            heading_deg: 280.0,
            pitch_deg: 5.0,
            roll_deg: -20.0,
        },
        Vector3::new(30.0, -50.0, -2.0),
    );
    s.angular_velocity_body_rad_s = Some(Vector3::new(0.01, 0.02, -0.05));
    s.acceleration_ned_m_s2 = Some(Vector3::new(0.5, -0.25, 0.125));
    s
}

fn config(kind: AircraftKind, alg: DrAlgorithm, version: DisVersion) -> EntityConfig {
    let mut c = EntityConfig::new(
        EntityIdentity::new(42, 7, 1001).unwrap(),
        kind,
        Marking::new("N172SP").unwrap(),
    );
    c.dr_algorithm = alg;
    c.version = version;
    c.exercise_id = 3;
    c.force = ForceId::Neutral;
    c
}

#[test]
fn bytes_at_the_standard_offsets() {
    let e = sample_state().to_ecef().unwrap();
    for (kind, type_bytes) in [
        (
            AircraftKind::CESSNA_172_SKYHAWK,
            [1u8, 2, 0, 225, 85, 11, 1, 0],
        ),
        (
            AircraftKind::SMALL_CIVIL_FIXED_WING,
            [1u8, 2, 0, 0, 85, 0, 0, 0],
        ),
    ] {
        for (alg, code) in [
            (DrAlgorithm::Fpw, 2u8),
            (DrAlgorithm::Rpw, 3),
            (DrAlgorithm::Rvw, 4),
            (DrAlgorithm::Fvw, 5),
        ] {
            for (version, vbyte) in [(DisVersion::V6, 6u8), (DisVersion::V7, 7)] {
                let cfg = config(kind, alg, version);
                let wire = WireState::new(&e, alg);
                let mut buf = BytesMut::new();
                let n = encode_entity_state(&cfg, &wire, &mut buf).unwrap();
                let b = &buf[..];
                assert_eq!((n, b.len()), (144, 144));
                // Header.
                assert_eq!(
                    &b[0..4],
                    &[vbyte, 3, 1, 1],
                    "version, exercise, type, family"
                );
                assert_eq!(u32_at(b, 4), dis_timestamp(1800.0).to_u32());
                assert_eq!(u16_at(b, 8), 144);
                // Body.
                assert_eq!((u16_at(b, 12), u16_at(b, 14), u16_at(b, 16)), (42, 7, 1001));
                assert_eq!(
                    (b[18], b[19]),
                    (3, 0),
                    "force Neutral, no variable parameters"
                );
                assert_eq!(&b[20..28], &type_bytes);
                assert_eq!(&b[28..36], &[0; 8], "alternative type");
                let v: Vec<f32> = (0..3).map(|i| f32_at(b, 36 + 4 * i)).collect();
                assert_eq!(v, wire.velocity_m_s);
                let p: Vec<f64> = (0..3).map(|i| f64_at(b, 48 + 8 * i)).collect();
                assert_eq!(p, wire.location_m.as_slice());
                let o: Vec<f32> = (0..3).map(|i| f32_at(b, 72 + 4 * i)).collect();
                assert_eq!(o, wire.orientation_rad);
                assert_eq!(u32_at(b, 84), 0, "appearance: default air platform");
                assert_eq!(b[88], code, "dead-reckoning algorithm");
                assert_eq!(&b[89..104], &[0; 15], "other DR parameters");
                let a: Vec<f32> = (0..3).map(|i| f32_at(b, 104 + 4 * i)).collect();
                let w: Vec<f32> = (0..3).map(|i| f32_at(b, 116 + 4 * i)).collect();
                assert_eq!(a, wire.acceleration_m_s2);
                assert_eq!(w, wire.angular_velocity_rad_s);
                assert_eq!(a != [0.0; 3], alg.accelerates(), "{alg:?}");
                assert_eq!(w != [0.0; 3], alg.rotates(), "{alg:?}");
                assert_eq!(b[128], 1, "marking character set ASCII");
                assert_eq!(
                    &b[129..140],
                    b"N172SP     ",
                    "marking, space padded by dis-rs"
                );
                assert_eq!(u32_at(b, 140), 0, "capabilities");
            }
        }
    }
}

#[test]
fn dis_rs_parses_what_it_wrote() {
    let e = sample_state().to_ecef().unwrap();
    let cfg = config(
        AircraftKind::CESSNA_172_SKYHAWK,
        DrAlgorithm::Rvw,
        DisVersion::V7,
    );
    let wire = WireState::new(&e, cfg.dr_algorithm);
    let mut buf = BytesMut::new();
    encode_entity_state(&cfg, &wire, &mut buf).unwrap();
    let pdus = fdm_dis::dis_rs::parse(&buf).unwrap();
    assert_eq!(pdus.len(), 1);
    let PduBody::EntityState(es) = &pdus[0].body else {
        panic!("not an entity state: {:?}", pdus[0].body)
    };
    assert_eq!(
        es.entity_type,
        AircraftKind::CESSNA_172_SKYHAWK.entity_type()
    );
    assert_eq!(es.force_id, ForceId::Neutral);
    assert_eq!(es.entity_marking.marking_string, "N172SP");
    assert_eq!(es.entity_location.x_coordinate, wire.location_m.x);
    assert_eq!(es.entity_orientation.theta, wire.orientation_rad[1]);
    assert_eq!(
        DrAlgorithm::from_dis(es.dead_reckoning_parameters.algorithm),
        Some(DrAlgorithm::Rvw)
    );
}

#[test]
fn timestamps() {
    // Half an hour is 2^30 units; relative flag (bit 0) clear.
    assert_eq!(dis_timestamp(1800.0).to_u32(), 1 << 31);
    assert_eq!(dis_timestamp(0.0).to_u32(), 0);
    assert_eq!(dis_timestamp(3600.0).to_u32(), 0, "wraps at the hour");
    assert_eq!(dis_timestamp(5400.0).to_u32(), 1 << 31);
    // Just below the hour: the largest count, 2^31 - 1, shifted.
    assert_eq!(dis_timestamp(3600.0 - 1e-9).to_u32(), 0xFFFF_FFFE);
    for bad in [f64::NAN, -1.0, f64::INFINITY] {
        assert_eq!(dis_timestamp(bad).to_u32(), 0);
    }
}

#[test]
fn marking_and_id_validation() {
    assert!(Marking::new("ABCDEFGHIJK").is_ok());
    assert!(matches!(
        Marking::new("ABCDEFGHIJKL"),
        Err(DisOutputError::MarkingTooLong(_))
    ));
    assert!(matches!(
        Marking::new("CAFÉ"),
        Err(DisOutputError::MarkingNotAscii(_))
    ));
    assert!(matches!(
        Marking::new("A\0B"),
        Err(DisOutputError::MarkingNotAscii(_))
    ));
    assert!(Marking::new("").is_ok());
    for (s, a, e) in [
        (0, 1, 1),
        (1, 0, 1),
        (1, 1, 0),
        (0xFFFF, 1, 1),
        (1, 0xFFFF, 1),
        (1, 1, 0xFFFE),
    ] {
        assert!(
            matches!(
                EntityIdentity::new(s, a, e),
                Err(DisOutputError::ReservedId { .. })
            ),
            "{s}:{a}:{e}"
        );
    }
    assert!(EntityIdentity::new(0xFFFE, 0xFFFE, 0xFFFD).is_ok());
}

/// `update_ecef` is `update` without the geodetic step: for the ECEF state
/// `update` computes, the very same bytes; a non-finite ECEF state is refused
/// (naming the field) and leaves the publisher unchanged.
#[test]
fn update_ecef_is_update_for_the_same_ecef_state() {
    use fdm_dis::{DrThresholds, EcefState, EntityPublisher};
    let config = EntityConfig::new(
        EntityIdentity::new(1, 2, 3).unwrap(),
        AircraftKind::CESSNA_172_SKYHAWK,
        Marking::new("N172SP").unwrap(),
    );
    let mut a = EntityPublisher::new(config.clone(), DrThresholds::default()).unwrap();
    let mut b = EntityPublisher::new(config, DrThresholds::default()).unwrap();
    let s = sample_state();
    let ecef = s.to_ecef().unwrap();
    let rebuilt = EcefState::new(
        ecef.time_s,
        ecef.location_m,
        ecef.body_to_ecef,
        ecef.velocity_m_s,
        ecef.acceleration_m_s2,
        ecef.angular_velocity_body_rad_s,
    );
    assert_eq!(rebuilt, ecef);
    let from_geodetic = a.update(&s).unwrap().unwrap().bytes.to_vec();
    let mut bad = rebuilt;
    bad.velocity_m_s.y = f64::NAN;
    assert_eq!(
        b.update_ecef(&bad),
        Err(DisOutputError::NonFinite("velocity_m_s"))
    );
    assert_eq!(b.counts().frames, 0);
    let from_ecef = b.update_ecef(&rebuilt).unwrap().unwrap().bytes.to_vec();
    assert_eq!(from_geodetic, from_ecef);
}

/// `type_label` prints the seven numbers of an entity type with dots, in the
/// order kind, domain, country, category, subcategory, specific, extra (the
/// documented `1.2.225.85.11.1.0` of the Cessna 172 Skyhawk), each field in
/// its place: a type whose seven numbers all differ, and the country's full
/// 16 bits.
#[test]
fn type_labels_are_the_seven_numbers_in_order() {
    use fdm_dis::type_label;
    assert_eq!(
        type_label(&AircraftKind::CESSNA_172_SKYHAWK.entity_type()),
        "1.2.225.85.11.1.0"
    );
    assert_eq!(
        type_label(&AircraftKind::SMALL_CIVIL_FIXED_WING.entity_type()),
        "1.2.0.85.0.0.0"
    );
    let all_different = AircraftKind {
        kind: 1,
        domain: 2,
        country: 260,
        category: 4,
        subcategory: 5,
        specific: 6,
        extra: 7,
    };
    assert_eq!(type_label(&all_different.entity_type()), "1.2.260.4.5.6.7");
}

/// An entity identifier reads `site:application:entity`.
#[test]
fn entity_identities_read_site_application_entity() {
    let id = EntityIdentity::new(1, 2, 3).unwrap();
    assert_eq!(id.to_string(), "1:2:3");
    assert_eq!(
        EntityIdentity::new(65534, 400, 9).unwrap().to_string(),
        "65534:400:9"
    );
}

/// The four world-frame dead-reckoning models: their standard names, their
/// codes on the wire (2 to 5, as the type's documentation lists them), and
/// back from a decoded field; any other algorithm (static, the body-frame
/// models) is none of them.
#[test]
fn dead_reckoning_models_have_their_names_and_codes() {
    use fdm_dis::dis_rs::enumerations::DeadReckoningAlgorithm;
    for (model, label, code) in [
        (DrAlgorithm::Fpw, "DRM(F,P,W)", 2_u8),
        (DrAlgorithm::Rpw, "DRM(R,P,W)", 3),
        (DrAlgorithm::Rvw, "DRM(R,V,W)", 4),
        (DrAlgorithm::Fvw, "DRM(F,V,W)", 5),
    ] {
        assert_eq!(model.label(), label);
        assert_eq!(u8::from(model.to_dis()), code, "{label}");
        assert_eq!(
            DrAlgorithm::from_dis(model.to_dis()),
            Some(model),
            "{label}"
        );
        assert_eq!(
            DrAlgorithm::from_dis(DeadReckoningAlgorithm::from(code)),
            Some(model),
            "{label}"
        );
    }
    for other in [0_u8, 1, 6, 7, 8, 9] {
        assert_eq!(
            DrAlgorithm::from_dis(DeadReckoningAlgorithm::from(other)),
            None,
            "code {other}"
        );
    }
}

/// An entity publisher counts its frames and each PDU under its reason
/// (`PublisherCounts`): an aircraft at rest sends its first PDU, then one
/// for a 10 m jump (position threshold 1 m), one for a 10° turn (3°), one
/// when the 5 s heartbeat falls due, and one when the clock goes back; the
/// frames in between send nothing and are counted as frames only.
#[test]
fn each_pdu_is_counted_under_its_reason() {
    use fdm_dis::{DrThresholds, EcefState, EntityPublisher, PublisherCounts, SendReason};
    use nalgebra::Rotation3;
    let config = EntityConfig::new(
        EntityIdentity::new(1, 2, 3).unwrap(),
        AircraftKind::CESSNA_172_SKYHAWK,
        Marking::new("N172SP").unwrap(),
    );
    let mut publisher = EntityPublisher::new(config, DrThresholds::default()).unwrap();
    let base = sample_state().to_ecef().unwrap();
    let at_rest = |time_s: f64, location_m: Vector3<f64>, turn_deg: f64| {
        EcefState::new(
            time_s,
            location_m,
            base.body_to_ecef
                * Rotation3::from_axis_angle(&Vector3::z_axis(), turn_deg.to_radians()).matrix(),
            Vector3::zeros(),
            Vector3::zeros(),
            Vector3::zeros(),
        )
    };
    let moved = base.location_m + Vector3::new(10.0, 0.0, 0.0);
    let mut reasons = Vec::new();
    for state in [
        at_rest(0.0, base.location_m, 0.0),
        at_rest(0.1, base.location_m, 0.0),
        at_rest(0.2, moved, 0.0),
        at_rest(0.3, moved, 10.0),
        at_rest(0.4, moved, 10.0),
        at_rest(6.0, moved, 10.0),
        at_rest(1.0, moved, 10.0),
    ] {
        reasons.push(publisher.update_ecef(&state).unwrap().map(|d| d.reason));
    }
    assert_eq!(
        reasons,
        [
            Some(SendReason::First),
            None,
            Some(SendReason::PositionError),
            Some(SendReason::OrientationError),
            None,
            Some(SendReason::Heartbeat),
            Some(SendReason::ClockReset),
        ]
    );
    assert_eq!(
        publisher.counts(),
        PublisherCounts {
            frames: 7,
            sent: 5,
            first_or_reset: 2,
            position: 1,
            orientation: 1,
            heartbeat: 1,
        }
    );
}
