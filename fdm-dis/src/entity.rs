//! What identifies one aircraft on a DIS exercise, and the Entity State PDU
//! built from its state with dis-rs.

use bytes::BytesMut;
use dis_rs::entity_state::model::{
    DrOtherParameters, DrParameters, EntityAppearance, EntityMarking, EntityState,
};
use dis_rs::enumerations::{
    AirPlatformAppearance, Country, DeadReckoningAlgorithm, EntityKind, ForceId, PduType,
    PlatformDomain, ProtocolVersion,
};
use dis_rs::model::{
    EntityId, EntityType, Location, Orientation, Pdu, PduHeader, TimeUnits, Timestamp, VectorF32,
};
use dis_rs::BodyRaw;
use nalgebra::Vector3;

use crate::error::DisOutputError;
use crate::frames::{DisEuler, EcefState};

/// SISO-REF-010 country code of the United States of America.
pub const COUNTRY_USA: u16 = 225;
/// SISO-REF-010 Platform-Air category 85, "Civilian Fixed Wing Aircraft,
/// Small (up to 12,500 lbs / 5,670 kg)".
pub const CATEGORY_CIVIL_FIXED_WING_SMALL: u8 = 85;
/// Subcategory 11 of USA / category 85: "Single Piston Engine".
pub const SUBCATEGORY_SINGLE_PISTON: u8 = 11;
/// Specific 1 of USA / 85 / 11: "Cessna 172 Skyhawk".
pub const SPECIFIC_CESSNA_172_SKYHAWK: u8 = 1;

/// An aircraft's DIS entity type (SISO-REF-010's seven numbers), a value:
/// a model states its own, and a new model needs no change here. Two
/// common ones are constants, named for what they are in DIS (the project's
/// models pick theirs in the run library).
///
/// Values from SISO-REF-010 (the DIS enumerations; dis-rs 0.14 is generated
/// from version 35 of that document):
///
/// | constant (model) | kind | domain | country | category | subcategory | specific | extra |
/// | --- | --- | --- | --- | --- | --- | --- | --- |
/// | `CESSNA_172_SKYHAWK` (Palmer's Cessna 172) | 1 Platform | 2 Air | 225 USA | 85 Civilian fixed wing, small | 11 Single piston engine | 1 Cessna 172 Skyhawk | 0 |
/// | `SMALL_CIVIL_FIXED_WING` (Bourg's generic aircraft) | 1 Platform | 2 Air | 0 Other | 85 Civilian fixed wing, small | 0 Other | 0 | 0 |
///
/// SISO-REF-010 also lists a Cessna 172 as USA / 40 "Trainer" / 1 (the
/// military T-41 Mescalero); the civil entry is the one for a civil Skyhawk.
/// Bourg's aircraft is no real type and no nation's design (about 985 kg,
/// one thrust force), so only its class is stated: a small civil fixed-wing
/// aircraft, country and subcategory "Other".
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AircraftKind {
    /// Entity kind (1: platform).
    pub kind: u8,
    /// Domain (2: air).
    pub domain: u8,
    /// Country (SISO-REF-010 code; 0: other).
    pub country: u16,
    /// Category within kind, domain and country.
    pub category: u8,
    /// Subcategory.
    pub subcategory: u8,
    /// Specific type.
    pub specific: u8,
    /// Extra.
    pub extra: u8,
}

impl AircraftKind {
    /// A Cessna 172 Skyhawk: 1.2.225.85.11.1.0 (Palmer's model flies as one).
    pub const CESSNA_172_SKYHAWK: Self = Self {
        kind: 1,
        domain: 2,
        country: COUNTRY_USA,
        category: CATEGORY_CIVIL_FIXED_WING_SMALL,
        subcategory: SUBCATEGORY_SINGLE_PISTON,
        specific: SPECIFIC_CESSNA_172_SKYHAWK,
        extra: 0,
    };

    /// A small civil fixed-wing aircraft of no stated country or type:
    /// 1.2.0.85.0.0.0 (Bourg's model, and the run library's default for a
    /// model that states none).
    pub const SMALL_CIVIL_FIXED_WING: Self = Self {
        kind: 1,
        domain: 2,
        country: 0,
        category: CATEGORY_CIVIL_FIXED_WING_SMALL,
        subcategory: 0,
        specific: 0,
        extra: 0,
    };

    /// The dis-rs entity type of these seven numbers.
    #[must_use]
    pub fn entity_type(self) -> EntityType {
        EntityType::default()
            .with_kind(EntityKind::from(self.kind))
            .with_domain(PlatformDomain::from(self.domain))
            .with_country(Country::from(self.country))
            .with_category(self.category)
            .with_subcategory(self.subcategory)
            .with_specific(self.specific)
            .with_extra(self.extra)
    }
}

/// `kind.domain.country.category.subcategory.specific.extra` of a DIS entity
/// type, as `sim-cli`'s reports and `dis-listen` print it (e.g.
/// `1.2.225.85.11.1.0` for [`AircraftKind::CESSNA_172_SKYHAWK`]).
#[must_use]
pub fn type_label(t: &EntityType) -> String {
    format!(
        "{}.{}.{}.{}.{}.{}.{}",
        u8::from(t.kind),
        u8::from(t.domain),
        u16::from(t.country),
        t.category,
        t.subcategory,
        t.specific,
        t.extra
    )
}

/// A DIS entity identifier: site, application and entity numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct EntityIdentity {
    /// Site number.
    pub site: u16,
    /// Application number within the site.
    pub application: u16,
    /// Entity number within the application.
    pub entity: u16,
}

impl EntityIdentity {
    /// A validated identifier: site and application in `1..=0xFFFE`, entity
    /// in `1..=0xFFFD` (DIS reserves 0 for "none", 0xFFFF for "all" and entity
    /// 0xFFFE for "request an id").
    ///
    /// # Errors
    /// [`DisOutputError::ReservedId`].
    pub fn new(site: u16, application: u16, entity: u16) -> Result<Self, DisOutputError> {
        for (field, value, max) in [
            ("site", site, 0xFFFE),
            ("application", application, 0xFFFE),
            ("entity", entity, 0xFFFD),
        ] {
            if value == 0 || value > max {
                return Err(DisOutputError::ReservedId { field, value });
            }
        }
        Ok(Self {
            site,
            application,
            entity,
        })
    }

    fn to_dis(self) -> EntityId {
        EntityId::new(self.site, self.application, self.entity)
    }

    /// The identifier of a decoded PDU (not validated: a receiver takes what
    /// it gets).
    #[must_use]
    pub fn from_dis(id: &EntityId) -> Self {
        Self {
            site: id.simulation_address.site_id,
            application: id.simulation_address.application_id,
            entity: id.entity_id,
        }
    }
}

impl core::fmt::Display for EntityIdentity {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{}:{}:{}", self.site, self.application, self.entity)
    }
}

/// An entity marking (a callsign): 1 to 11 printable ASCII characters, sent
/// with the ASCII character set.
///
/// dis-rs pads it with spaces on the wire, and its parser drops trailing
/// spaces and trailing characters that are not letters or digits, so a
/// marking that ends in letters or digits comes back unchanged.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Marking(String);

impl Marking {
    /// A validated marking.
    ///
    /// # Errors
    /// [`DisOutputError::MarkingTooLong`] beyond 11 characters,
    /// [`DisOutputError::MarkingNotAscii`] for anything outside 0x20..=0x7E
    /// (an empty marking is accepted).
    pub fn new(text: &str) -> Result<Self, DisOutputError> {
        if !text.bytes().all(|b| (0x20..=0x7E).contains(&b)) {
            return Err(DisOutputError::MarkingNotAscii(text.to_owned()));
        }
        if text.len() > 11 {
            return Err(DisOutputError::MarkingTooLong(text.to_owned()));
        }
        Ok(Self(text.to_owned()))
    }

    /// The characters.
    #[must_use]
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

/// The dead-reckoning models this crate sends and extrapolates: the four
/// whose rates are in world (ECEF) coordinates.
///
/// Letters as in the standard: F/R = fixed or rotating orientation, P/V =
/// constant velocity or constant acceleration, W = world frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum DrAlgorithm {
    /// DRM(F,P,W), code 2: `P = P₀ + V₀ Δt`, orientation held.
    Fpw,
    /// DRM(R,P,W), code 3: `P = P₀ + V₀ Δt`, orientation rotated by the body
    /// angular velocity.
    Rpw,
    /// DRM(R,V,W), code 4: `P = P₀ + V₀ Δt + ½ A₀ Δt²`, orientation rotated
    /// by the body angular velocity. The default: an aircraft manoeuvres.
    #[default]
    Rvw,
    /// DRM(F,V,W), code 5: `P = P₀ + V₀ Δt + ½ A₀ Δt²`, orientation held.
    Fvw,
}

impl DrAlgorithm {
    /// The PDU's dead-reckoning algorithm field.
    #[must_use]
    pub fn to_dis(self) -> DeadReckoningAlgorithm {
        match self {
            Self::Fpw => DeadReckoningAlgorithm::DRM_FPW_ConstantVelocityLowAccelerationLinearMotionEntity,
            Self::Rpw => DeadReckoningAlgorithm::DRM_RPW_ConstantVelocityLowAccelerationLinearMotionEntityWithExtrapolationOfOrientation,
            Self::Rvw => DeadReckoningAlgorithm::DRM_RVW_HighSpeedOrManeuveringEntityWithExtrapolationOfOrientation,
            Self::Fvw => DeadReckoningAlgorithm::DRM_FVW_HighSpeedOrManeuveringEntity,
        }
    }

    /// The model of a decoded algorithm field, if it is one of these four.
    #[must_use]
    pub fn from_dis(algorithm: DeadReckoningAlgorithm) -> Option<Self> {
        [Self::Fpw, Self::Rpw, Self::Rvw, Self::Fvw]
            .into_iter()
            .find(|a| a.to_dis() == algorithm)
    }

    /// The standard's name, e.g. `"DRM(R,V,W)"`.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::Fpw => "DRM(F,P,W)",
            Self::Rpw => "DRM(R,P,W)",
            Self::Rvw => "DRM(R,V,W)",
            Self::Fvw => "DRM(F,V,W)",
        }
    }

    /// Whether the orientation is extrapolated with the angular velocity
    /// (R models), so the PDU carries it.
    #[must_use]
    pub fn rotates(self) -> bool {
        matches!(self, Self::Rpw | Self::Rvw)
    }

    /// Whether the position is extrapolated with the acceleration (V models),
    /// so the PDU carries it.
    #[must_use]
    pub fn accelerates(self) -> bool {
        matches!(self, Self::Rvw | Self::Fvw)
    }
}

/// Which DIS version the PDUs are written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum DisVersion {
    /// IEEE 1278.1a-1998 (protocol version 6).
    V6,
    /// IEEE 1278.1-2012 (protocol version 7), the default.
    #[default]
    V7,
}

impl DisVersion {
    fn to_dis(self) -> ProtocolVersion {
        match self {
            Self::V6 => ProtocolVersion::IEEE1278_1A1998,
            Self::V7 => ProtocolVersion::IEEE1278_12012,
        }
    }
}

/// Everything about one aircraft's Entity State PDUs that does not change
/// from frame to frame.
#[derive(Debug, Clone, PartialEq)]
pub struct EntityConfig {
    /// DIS exercise id (1 by default; receivers filter on it).
    pub exercise_id: u8,
    /// Site, application and entity numbers.
    pub id: EntityIdentity,
    /// SISO-REF-010 entity type (see [`AircraftKind::entity_type`]).
    pub entity_type: EntityType,
    /// Force the entity belongs to (default `Friendly`, code 1).
    pub force: ForceId,
    /// Callsign.
    pub marking: Marking,
    /// Dead-reckoning model announced in the PDU and used by the sender-side
    /// model ([`crate::DeadReckoner`]).
    pub dr_algorithm: DrAlgorithm,
    /// DIS version written.
    pub version: DisVersion,
}

impl EntityConfig {
    /// A configuration with the defaults: exercise 1, force Friendly,
    /// DRM(R,V,W), DIS 7.
    #[must_use]
    pub fn new(id: EntityIdentity, kind: AircraftKind, marking: Marking) -> Self {
        Self {
            exercise_id: 1,
            id,
            entity_type: kind.entity_type(),
            force: ForceId::Friendly,
            marking,
            dr_algorithm: DrAlgorithm::default(),
            version: DisVersion::default(),
        }
    }
}

/// Exactly what a receiver gets from one Entity State PDU (the wire's `f32`s
/// for orientation and rates), and so what the sender-side dead-reckoning
/// model must extrapolate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WireState {
    /// Simulation time of the state, seconds.
    pub time_s: f64,
    /// Location, ECEF metres (`f64` on the wire).
    pub location_m: Vector3<f64>,
    /// ψ, θ, φ as sent, radians.
    pub orientation_rad: [f32; 3],
    /// Linear velocity, ECEF, m/s.
    pub velocity_m_s: [f32; 3],
    /// Linear acceleration, ECEF, m/s² (zero unless the model is a V model).
    pub acceleration_m_s2: [f32; 3],
    /// Angular velocity, body axes, rad/s (zero unless the model is an R
    /// model).
    pub angular_velocity_rad_s: [f32; 3],
}

fn f32x3(v: &Vector3<f64>) -> [f32; 3] {
    // The wire holds f32: rounding to nearest is the intended conversion.
    #[allow(clippy::cast_possible_truncation)]
    [v.x as f32, v.y as f32, v.z as f32]
}

impl WireState {
    /// The fields of the PDU for `state` under `algorithm`: the acceleration
    /// is sent only by V models, the angular velocity only by R models
    /// (zeros otherwise, so that a receiver using either model extrapolates
    /// exactly as the sender's model does).
    #[must_use]
    pub fn new(state: &EcefState, algorithm: DrAlgorithm) -> Self {
        let e = &state.orientation;
        #[allow(clippy::cast_possible_truncation)]
        let orientation_rad = [e.psi_rad as f32, e.theta_rad as f32, e.phi_rad as f32];
        Self {
            time_s: state.time_s,
            location_m: state.location_m,
            orientation_rad,
            velocity_m_s: f32x3(&state.velocity_m_s),
            acceleration_m_s2: if algorithm.accelerates() {
                f32x3(&state.acceleration_m_s2)
            } else {
                [0.0; 3]
            },
            angular_velocity_rad_s: if algorithm.rotates() {
                f32x3(&state.angular_velocity_body_rad_s)
            } else {
                [0.0; 3]
            },
        }
    }

    /// The orientation as sent, as [`DisEuler`].
    #[must_use]
    pub fn orientation(&self) -> DisEuler {
        let [psi, theta, phi] = self.orientation_rad;
        DisEuler {
            psi_rad: f64::from(psi),
            theta_rad: f64::from(theta),
            phi_rad: f64::from(phi),
        }
    }
}

/// The PDU timestamp for a simulation time: DIS counts time since the start
/// of the hour in units of 3600 s / 2³¹ (about 1.68 µs). The simulation time
/// is not wall-clock time, so the timestamp is marked *relative*; its hour
/// wraps every 3600 s of simulation time. Negative or non-finite times give
/// 0.
#[must_use]
pub fn dis_timestamp(time_s: f64) -> Timestamp {
    const UNITS_PER_HOUR: f64 = 2_147_483_648.0; // 2^31
    let within_hour = if time_s.is_finite() && time_s > 0.0 {
        time_s.rem_euclid(3600.0)
    } else {
        0.0
    };
    // In [0, 2^31); `min` guards the rounding at the top end.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let units = ((within_hour / 3600.0 * UNITS_PER_HOUR) as u32).min(0x7FFF_FFFF);
    Timestamp::Relative(TimeUnits::new(units).unwrap_or(TimeUnits::MAX))
}

/// The dis-rs Entity State PDU for one aircraft.
#[must_use]
pub fn entity_state_pdu(config: &EntityConfig, wire: &WireState) -> Pdu {
    let [vx, vy, vz] = wire.velocity_m_s;
    let [ax, ay, az] = wire.acceleration_m_s2;
    let [wx, wy, wz] = wire.angular_velocity_rad_s;
    let [psi, theta, phi] = wire.orientation_rad;
    let body = EntityState::builder()
        .with_entity_id(config.id.to_dis())
        .with_force_id(config.force)
        .with_entity_type(config.entity_type)
        .with_velocity(VectorF32::new(vx, vy, vz))
        .with_location(Location::new(
            wire.location_m.x,
            wire.location_m.y,
            wire.location_m.z,
        ))
        .with_orientation(Orientation::new(psi, theta, phi))
        .with_appearance(EntityAppearance::AirPlatform(
            AirPlatformAppearance::default(),
        ))
        .with_dead_reckoning_parameters(
            DrParameters::default()
                .with_algorithm(config.dr_algorithm.to_dis())
                .with_parameters(DrOtherParameters::None([0; 15]))
                .with_linear_acceleration(VectorF32::new(ax, ay, az))
                .with_angular_velocity(VectorF32::new(wx, wy, wz)),
        )
        .with_marking(EntityMarking::new_ascii(config.marking.as_str()))
        .build()
        .into_pdu_body();
    let header = PduHeader::new(
        config.version.to_dis(),
        config.exercise_id,
        PduType::EntityState,
    );
    Pdu::finalize_from_parts(header, body, dis_timestamp(wire.time_s))
}

/// Length of an Entity State PDU without variable parameters, bytes
/// (12-byte header + 132-byte body).
pub const ENTITY_STATE_PDU_LEN: usize = 144;

/// Serialises an Entity State PDU into `buf` (cleared first) with dis-rs;
/// returns the number of bytes.
///
/// # Errors
/// [`DisOutputError::Encode`] if dis-rs refuses (it does when the buffer's
/// capacity is too small; this function reserves enough first).
pub fn encode_entity_state(
    config: &EntityConfig,
    wire: &WireState,
    buf: &mut BytesMut,
) -> Result<usize, DisOutputError> {
    let pdu = entity_state_pdu(config, wire);
    buf.clear();
    buf.reserve(usize::from(pdu.pdu_length()));
    pdu.serialize(buf)
        .map(usize::from)
        .map_err(|e| DisOutputError::Encode(e.to_string()))
}

/// Makes `pdu`, an Entity State PDU that [`encode_entity_state`] wrote for
/// some configuration and any wire state, the PDU of `wire` for the same
/// configuration, byte for byte what [`encode_entity_state`] would write:
/// only the fields that come from the wire state are written (the header's
/// timestamp, the velocity, location and orientation, the dead-reckoning
/// acceleration and angular velocity, at the standard's offsets, big-endian
/// as dis-rs writes them); the rest (header, identity, type, appearance,
/// dead-reckoning algorithm, marking, capabilities) depends on the
/// configuration alone and is kept. Straight stores instead of dis-rs's PDU
/// value (its marking's `String`) and many small writes; the test
/// `rewriting_a_pdu_is_encoding_it` compares the two.
pub(crate) fn rewrite_entity_state(pdu: &mut [u8; ENTITY_STATE_PDU_LEN], wire: &WireState) {
    fn put<const N: usize>(pdu: &mut [u8], at: usize, bytes: [u8; N]) {
        pdu[at..at + N].copy_from_slice(&bytes);
    }
    put(pdu, 4, u32::from(dis_timestamp(wire.time_s)).to_be_bytes());
    for (k, v) in wire.velocity_m_s.iter().enumerate() {
        put(pdu, 36 + 4 * k, v.to_be_bytes());
    }
    for (k, x) in wire.location_m.iter().enumerate() {
        put(pdu, 48 + 8 * k, x.to_be_bytes());
    }
    for (k, o) in wire.orientation_rad.iter().enumerate() {
        put(pdu, 72 + 4 * k, o.to_be_bytes());
    }
    for (k, a) in wire.acceleration_m_s2.iter().enumerate() {
        put(pdu, 104 + 4 * k, a.to_be_bytes());
    }
    for (k, w) in wire.angular_velocity_rad_s.iter().enumerate() {
        put(pdu, 116 + 4 * k, w.to_be_bytes());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tracker::tests::unit_xorshift;

    /// A number of any kind from `u`: every `f32` or `f64` bit pattern
    /// class the wire can see (zeros of both signs, subnormals, the
    /// extremes, infinities, NaNs with payloads, ordinary values).
    fn any_f64(u: &mut impl FnMut() -> f64) -> f64 {
        let pick = u();
        let x = u();
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let bits = (x * 2f64.powi(53)) as u64;
        match (pick * 12.0) as u32 {
            0 => 0.0,
            1 => -0.0,
            2 => f64::from_bits(bits & 0x000F_FFFF_FFFF_FFFF | 1),
            3 => f64::MAX,
            4 => f64::MIN_POSITIVE,
            5 => f64::INFINITY,
            6 => f64::NEG_INFINITY,
            7 => f64::from_bits(0x7FF0_0000_0000_0000 | bits | 1),
            8 => f64::from_bits(bits.rotate_left(11) ^ bits),
            _ => (x - 0.5) * 2f64.powi((u() * 60.0) as i32 - 20),
        }
    }

    fn any_f32(u: &mut impl FnMut() -> f64) -> f32 {
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let bits = (u() * 2f64.powi(32)) as u32;
        match (u() * 10.0) as u32 {
            0 => f32::from_bits(bits),
            1 => f32::from_bits(bits & 0x007F_FFFF | 1),
            2 => f32::NAN,
            #[allow(clippy::cast_possible_truncation)]
            _ => any_f64(u) as f32,
        }
    }

    fn any_wire(u: &mut impl FnMut() -> f64) -> WireState {
        let time_s = match (u() * 8.0) as u32 {
            0 => any_f64(u),
            1 => 3600.0 * (u() * 10.0).floor() + (u() - 0.5) * 1e-9,
            2 => -u() * 100.0,
            _ => u() * 20_000.0,
        };
        let mut three = || [any_f32(u), any_f32(u), any_f32(u)];
        let (orientation_rad, velocity_m_s, acceleration_m_s2, angular_velocity_rad_s) =
            (three(), three(), three(), three());
        WireState {
            time_s,
            location_m: Vector3::new(any_f64(u), any_f64(u), any_f64(u)),
            orientation_rad,
            velocity_m_s,
            acceleration_m_s2,
            angular_velocity_rad_s,
        }
    }

    /// [`rewrite_entity_state`] of a PDU [`encode_entity_state`] wrote is
    /// what [`encode_entity_state`] writes for the new wire state, byte for
    /// byte: both DIS versions, the four dead-reckoning models, both
    /// aircraft kinds, forces, exercises, identities at the extremes and
    /// markings from empty to 11 characters; wire states with every class
    /// of `f32`/`f64` (zeros of both signs, subnormals, extremes,
    /// infinities, NaNs with payloads) and times around the timestamp's
    /// hour, negative and not finite; each PDU rewritten from the previous
    /// one, as a publisher does.
    #[test]
    fn rewriting_a_pdu_is_encoding_it() {
        let mut u = unit_xorshift(0xE27_17E5_7A7E_0144);
        let mut rewritten = 0;
        for case in 0..400 {
            let pick = |n: usize, u: &mut dyn FnMut() -> f64| {
                #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
                let k = (u() * n as f64) as usize;
                k.min(n - 1)
            };
            let markings = ["", "N", "N172SP", "PALMER00001", "a b~c!", "12345678901"];
            let id = [
                (1, 1, 1),
                (65534, 65534, 65533),
                (42, 7, 1001),
                (1, 65534, 2),
            ];
            let (site, application, entity) = id[pick(id.len(), &mut u)];
            let identity = EntityIdentity::new(site, application, entity).unwrap();
            let kind = [
                AircraftKind::CESSNA_172_SKYHAWK,
                AircraftKind::SMALL_CIVIL_FIXED_WING,
            ][case % 2];
            let mut config = EntityConfig::new(
                identity,
                kind,
                Marking::new(markings[pick(markings.len(), &mut u)]).unwrap(),
            );
            config.dr_algorithm = [
                DrAlgorithm::Fpw,
                DrAlgorithm::Rpw,
                DrAlgorithm::Rvw,
                DrAlgorithm::Fvw,
            ][(case / 2) % 4];
            config.version = [DisVersion::V6, DisVersion::V7][(case / 8) % 2];
            config.force = [ForceId::Other, ForceId::Friendly, ForceId::Opposing][case % 3];
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let exercise = (u() * 256.0) as u8;
            config.exercise_id = exercise;
            let mut buf = BytesMut::new();
            let n = encode_entity_state(&config, &any_wire(&mut u), &mut buf).unwrap();
            assert_eq!(n, ENTITY_STATE_PDU_LEN);
            let mut pdu: [u8; ENTITY_STATE_PDU_LEN] = buf[..].try_into().unwrap();
            for _ in 0..40 {
                let wire = any_wire(&mut u);
                rewrite_entity_state(&mut pdu, &wire);
                let mut want = BytesMut::new();
                encode_entity_state(&config, &wire, &mut want).unwrap();
                assert_eq!(&pdu[..], &want[..], "{config:?} {wire:?}");
                rewritten += 1;
            }
        }
        assert_eq!(rewritten, 400 * 40);
    }
}
