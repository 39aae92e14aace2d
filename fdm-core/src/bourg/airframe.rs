//! The airframe as data ([`Element`], [`Airframe`], with Bourg's airplane in
//! [`Airframe::bourg_default`]), its mass properties ([`MassProperties`]) and
//! the two bundled ([`BourgAircraft`]).

use core::fmt;

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use super::ops::{degrees_to_radians, determinant, inverse, normalize};
use crate::math::{cosf, sinf};

/// Which airfoil table an element flies with: the original's integer flap
/// code (`iFlap`).
///
/// On a wing, a trailing edge deflected down adds camber and lift; deflected up
/// it removes lift. So [`Flap::TrailingEdgeUp`] on the elevators pitches the
/// nose up, and on the port aileron (with the starboard one down) rolls left.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Flap {
    /// Code −1: the "flaps down" tables (more lift).
    TrailingEdgeDown,
    /// Code 0: the plain airfoil tables, no deflection.
    #[default]
    Neutral,
    /// Code +1: the "flaps up" tables (less lift).
    TrailingEdgeUp,
}

/// Maximum thrust, lb (the original's `_MAXTHRUST`).
pub const MAX_THRUST_LB: f32 = 3000.0;
/// Thrust change per thrust key press, lb (the original's `_DTHRUST`; the
/// book's listing uses 10, the reference numbers need 100).
pub const DELTA_THRUST_LB: f32 = 100.0;
/// Rudder incidence while a yaw key is held, degrees (+ for yaw left).
pub const RUDDER_DEFLECTION_DEG: f32 = 16.0;

impl Flap {
    /// The original's integer code: −1, 0 or +1.
    #[must_use]
    pub const fn code(self) -> i8 {
        match self {
            Self::TrailingEdgeDown => -1,
            Self::Neutral => 0,
            Self::TrailingEdgeUp => 1,
        }
    }

    /// The flap for an integer code, `None` unless it is −1, 0 or +1.
    #[must_use]
    pub const fn from_code(code: i8) -> Option<Self> {
        match code {
            -1 => Some(Self::TrailingEdgeDown),
            0 => Some(Self::Neutral),
            1 => Some(Self::TrailingEdgeUp),
            _ => None,
        }
    }
}

/// One of the airframe's eight point-mass lifting elements (the original's
/// `PointMass`).
///
/// Roles are fixed by index, as in the original: 0 and 3 are the outboard
/// wing sections with the ailerons (port, starboard), 1 and 2 the inboard
/// sections with the landing flaps (port, starboard), 4 and 5 the elevators
/// (port, starboard), 6 the all-moving vertical tail (rudder) and 7 the
/// fuselage, which only makes drag.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Element {
    /// Mass, slug.
    pub mass_slug: f32,
    /// Position in design coordinates, ft: measured from the tail (x forward),
    /// the centerline (y left) and the baseline (z up).
    pub design_position_ft: Vector3<f32>,
    /// Moments of inertia about the element's own axes `(Ixx, Iyy, Izz)`, slug·ft².
    pub local_inertia: Vector3<f32>,
    /// Incidence (rotation about the body y axis), degrees. For the rudder
    /// (element 6) this is the rigging; the rudder control adds to it.
    pub incidence_deg: f32,
    /// Dihedral (rotation about the body x axis), degrees; 90 for a vertical surface.
    pub dihedral_deg: f32,
    /// Planform area, ft².
    pub area_ft2: f32,
    /// The element's rigged flap setting: the table it flies with while no
    /// control deflects it (see [`BourgControls::element_flap`](super::BourgControls::element_flap)).
    pub flap: Flap,
}

/// An airframe: eight lifting elements (see [`Element`] for their fixed
/// roles).
///
/// Serialisable, so airframes can come from user files; check those with
/// [`validate`](Self::validate) (or build an [`BourgAircraft`] with
/// [`BourgAircraft::new`], which does).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Airframe {
    /// The elements, in the order of their roles.
    pub elements: [Element; 8],
}

/// One element of the default airframe's data: `(mass, design position, local
/// inertia, incidence, dihedral, area)`.
type ElementData = (f32, [f32; 3], [f32; 3], f32, f32, f32);

/// Bourg's airplane, element by element (the original's `float` literals).
const DEFAULT_ELEMENTS: [ElementData; 8] = [
    // 0: outboard port wing, aileron
    (
        6.56,
        [14.5, 12.0, 2.5],
        [13.92, 10.50, 24.00],
        -3.5,
        0.0,
        31.2,
    ),
    // 1: inboard port wing, landing flap
    (
        7.31,
        [14.5, 5.5, 2.5],
        [21.95, 12.22, 33.67],
        -3.5,
        0.0,
        36.4,
    ),
    // 2: inboard starboard wing, landing flap
    (
        7.31,
        [14.5, -5.5, 2.5],
        [21.95, 12.22, 33.67],
        -3.5,
        0.0,
        36.4,
    ),
    // 3: outboard starboard wing, aileron
    (
        6.56,
        [14.5, -12.0, 2.5],
        [13.92, 10.50, 24.00],
        -3.5,
        0.0,
        31.2,
    ),
    // 4: port elevator
    (
        2.62,
        [3.03, 2.5, 3.0],
        [0.837, 0.385, 1.206],
        0.0,
        0.0,
        10.8,
    ),
    // 5: starboard elevator
    (
        2.62,
        [3.03, -2.5, 3.0],
        [0.837, 0.385, 1.206],
        0.0,
        0.0,
        10.8,
    ),
    // 6: vertical tail / rudder
    (
        2.93,
        [2.25, 0.0, 5.0],
        [1.262, 1.942, 0.718],
        0.0,
        90.0,
        12.0,
    ),
    // 7: fuselage
    (
        31.8,
        [15.25, 0.0, 1.5],
        [66.30, 861.9, 861.9],
        0.0,
        0.0,
        84.0,
    ),
];

impl Airframe {
    /// Bourg's airplane (docs/bourg-model.md "The airframe"), all flaps neutral.
    #[must_use]
    pub fn bourg_default() -> Self {
        let element = |i: usize| {
            let (mass, dsg, inertia, incidence, dihedral, area) = DEFAULT_ELEMENTS[i];
            Element {
                mass_slug: mass,
                design_position_ft: Vector3::new(dsg[0], dsg[1], dsg[2]),
                local_inertia: Vector3::new(inertia[0], inertia[1], inertia[2]),
                incidence_deg: incidence,
                dihedral_deg: dihedral,
                area_ft2: area,
                flap: Flap::Neutral,
            }
        };
        Self {
            elements: core::array::from_fn(element),
        }
    }

    /// Checks a (user-supplied) airframe: every number finite, total mass
    /// positive, inertia tensor invertible with a finite inverse.
    ///
    /// # Errors
    /// The first problem found, as an [`AirframeError`].
    pub fn validate(&self) -> Result<(), AirframeError> {
        for (index, e) in self.elements.iter().enumerate() {
            let fields = [
                ("mass_slug", e.mass_slug),
                ("design_position_ft.x", e.design_position_ft.x),
                ("design_position_ft.y", e.design_position_ft.y),
                ("design_position_ft.z", e.design_position_ft.z),
                ("local_inertia.x", e.local_inertia.x),
                ("local_inertia.y", e.local_inertia.y),
                ("local_inertia.z", e.local_inertia.z),
                ("incidence_deg", e.incidence_deg),
                ("dihedral_deg", e.dihedral_deg),
                ("area_ft2", e.area_ft2),
            ];
            if let Some((field, _)) = fields.iter().find(|(_, v)| !f32::is_finite(*v)) {
                return Err(AirframeError::NonFinite {
                    element: index,
                    field,
                });
            }
        }
        let mass = MassProperties::from_airframe(self);
        let positive = mass.mass_slug > 0.0; // false for NaN
        if !positive || !f32::is_finite(mass.mass_slug) {
            return Err(AirframeError::NonPositiveMass {
                total_mass_slug: f64::from(mass.mass_slug),
            });
        }
        let d = determinant(&mass.inertia);
        let all_finite = |m: &Matrix3<f32>| m.iter().all(|v| f32::is_finite(*v));
        if d == 0.0 || !f32::is_finite(d) || !all_finite(&mass.inertia_inverse) {
            return Err(AirframeError::SingularInertia {
                determinant: f64::from(d),
            });
        }
        let derived_finite = f32::is_finite(mass.cg_ft.x)
            && f32::is_finite(mass.cg_ft.y)
            && f32::is_finite(mass.cg_ft.z)
            && all_finite(&mass.inertia);
        if !derived_finite {
            return Err(AirframeError::SingularInertia {
                determinant: f64::from(d),
            });
        }
        Ok(())
    }
}

impl Default for Airframe {
    fn default() -> Self {
        Self::bourg_default()
    }
}

/// Why an airframe was rejected by [`Airframe::validate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AirframeError {
    /// A number of an element is NaN or infinite.
    NonFinite {
        /// Index of the element (0..8).
        element: usize,
        /// Name of the field, e.g. `"design_position_ft.y"`.
        field: &'static str,
    },
    /// The total mass is zero, negative, or not finite.
    NonPositiveMass {
        /// The total mass, slug (widened to `f64`).
        total_mass_slug: f64,
    },
    /// The inertia tensor about the CG is singular (determinant 0, as the
    /// original computes it) or its inverse or the CG is not finite.
    SingularInertia {
        /// The determinant, slug³·ft⁶ (widened to `f64`).
        determinant: f64,
    },
}

impl fmt::Display for AirframeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFinite { element, field } => {
                write!(f, "element {element}: `{field}` is not a finite number")
            }
            Self::NonPositiveMass { total_mass_slug } => {
                write!(
                    f,
                    "total mass {total_mass_slug} slug is not a positive number"
                )
            }
            Self::SingularInertia { determinant } => write!(
                f,
                "the inertia tensor is singular or not finite (determinant {determinant})"
            ),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for AirframeError {}

/// Mass properties derived once from an airframe (the original's
/// `CalcAirplaneMassProperties`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MassProperties {
    /// Total mass, slug (67.71 for Bourg's airplane).
    pub mass_slug: f32,
    /// Centre of gravity in design coordinates, ft.
    pub cg_ft: Vector3<f32>,
    /// Each element's position relative to the CG (body axes), ft.
    pub cg_offsets_ft: [Vector3<f32>; 8],
    /// Each element's unit normal (body axes) at its rigged incidence and
    /// dihedral. The loads use the rudder's (element 6) at the current rudder
    /// incidence instead ([`BourgAircraft::rudder_normal`]).
    pub normals: [Vector3<f32>; 8],
    /// Inertia tensor about the CG, body axes, slug·ft².
    pub inertia: Matrix3<f32>,
    /// Its inverse as the original computes it, 1/(slug·ft²).
    pub inertia_inverse: Matrix3<f32>,
}

/// An element's unit normal for an incidence and a dihedral in degrees:
/// `Normalize((sin in, cos in · sin di, cos in · cos di))` with `in`, `di` in
/// radians, all in `f32` (the original's `sinf`/`cosf` and float products).
#[inline]
#[must_use]
pub fn element_normal(incidence_deg: f32, dihedral_deg: f32) -> Vector3<f32> {
    let inc = degrees_to_radians(incidence_deg);
    let dih = degrees_to_radians(dihedral_deg);
    normalize(&Vector3::new(
        sinf(inc),
        cosf(inc) * sinf(dih),
        cosf(inc) * cosf(dih),
    ))
}

impl MassProperties {
    /// Computes the mass properties in the original's order: normals; total
    /// mass summed over elements 0..7; first moment `Σ mᵢ·dsgᵢ` and
    /// CG = moment / mass; offsets `dsgᵢ − CG`; the inertia sums
    /// `Ixx = Σ [Iloc.x + m(cy² + cz²)]`, `Iyy = Σ [Iloc.y + m(cz² + cx²)]`,
    /// `Izz = Σ [Iloc.z + m(cx² + cy²)]`, `Ixy = Σ m(cx cy)`, `Ixz = Σ m(cx cz)`,
    /// `Iyz = Σ m(cy cz)`; the tensor `[Ixx −Ixy −Ixz; −Ixy Iyy −Iyz; −Ixz −Iyz Izz]`
    /// and its [`inverse`].
    ///
    /// No validation: a zero mass gives non-finite values (see
    /// [`Airframe::validate`]).
    #[must_use]
    pub fn from_airframe(airframe: &Airframe) -> Self {
        let elements = &airframe.elements;
        let normals = core::array::from_fn(|i| {
            element_normal(elements[i].incidence_deg, elements[i].dihedral_deg)
        });

        let mut mass = 0.0;
        for e in elements {
            mass += e.mass_slug;
        }

        let mut moment = Vector3::new(0.0, 0.0, 0.0);
        for e in elements {
            moment += e.design_position_ft * e.mass_slug;
        }
        let cg = moment / mass;
        let cg_offsets: [Vector3<f32>; 8] =
            core::array::from_fn(|i| elements[i].design_position_ft - cg);

        let (mut ixx, mut iyy, mut izz) = (0.0, 0.0, 0.0);
        let (mut ixy, mut ixz, mut iyz) = (0.0, 0.0, 0.0);
        for (e, c) in elements.iter().zip(&cg_offsets) {
            let (m, l) = (e.mass_slug, &e.local_inertia);
            ixx += l.x + m * (c.y * c.y + c.z * c.z);
            iyy += l.y + m * (c.z * c.z + c.x * c.x);
            izz += l.z + m * (c.x * c.x + c.y * c.y);
            ixy += m * (c.x * c.y);
            ixz += m * (c.x * c.z);
            iyz += m * (c.y * c.z);
        }
        let inertia = Matrix3::new(ixx, -ixy, -ixz, -ixy, iyy, -iyz, -ixz, -iyz, izz);

        Self {
            mass_slug: mass,
            cg_ft: cg,
            cg_offsets_ft: cg_offsets,
            normals,
            inertia,
            inertia_inverse: inverse(&inertia),
        }
    }
}

/// An airframe bundled with its mass properties, computed once: what
/// [`loads`](super::loads) and [`step`](super::step) take.
///
/// The fields are private so the two always agree; build one with
/// [`new`](Self::new) (validating) or [`bourg_default`](Self::bourg_default).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BourgAircraft {
    /// Maximum thrust a thrust-up action reaches, lb (the original's
    /// `_MAXTHRUST`, [`MAX_THRUST_LB`](MAX_THRUST_LB) by default).
    pub max_thrust_lb: f32,
    /// Thrust change per thrust-up/down action, lb (the original's
    /// `_DTHRUST`, [`DELTA_THRUST_LB`](DELTA_THRUST_LB) by default).
    pub delta_thrust_lb: f32,
    airframe: Airframe,
    mass: MassProperties,
    /// The rudder's normal for the incidences the controls produce (rigging
    /// + 0, +16, −16 degrees), so the loads need not recompute it each frame.
    rudder_normals: [(f32, Vector3<f32>); 3],
}

impl BourgAircraft {
    /// Validates the airframe and computes its mass properties.
    ///
    /// # Errors
    /// [`AirframeError`] from [`Airframe::validate`].
    pub fn new(airframe: Airframe) -> Result<Self, AirframeError> {
        airframe.validate()?;
        Ok(Self::from_valid(airframe))
    }

    /// Bourg's airplane ([`Airframe::bourg_default`]).
    #[must_use]
    pub fn bourg_default() -> Self {
        Self::from_valid(Airframe::bourg_default())
    }

    fn from_valid(airframe: Airframe) -> Self {
        let rudder = &airframe.elements[6];
        let deflection = RUDDER_DEFLECTION_DEG;
        let normal_at = |deflection: f32| {
            let incidence = rudder.incidence_deg + deflection;
            (incidence, element_normal(incidence, rudder.dihedral_deg))
        };
        Self {
            max_thrust_lb: MAX_THRUST_LB,
            delta_thrust_lb: DELTA_THRUST_LB,
            mass: MassProperties::from_airframe(&airframe),
            rudder_normals: [
                normal_at(0.0),
                normal_at(deflection),
                normal_at(-deflection),
            ],
            airframe,
        }
    }

    /// The rudder's (element 6's) unit normal at an incidence in degrees:
    /// [`element_normal`] of the incidence and the rudder's dihedral, taken
    /// from a table precomputed for the incidences the controls produce
    /// (identical values; `+0` and `−0` give the same normal) and computed
    /// otherwise.
    #[inline]
    #[must_use]
    pub fn rudder_normal(&self, incidence_deg: f32) -> Vector3<f32> {
        for (incidence, normal) in &self.rudder_normals {
            if *incidence == incidence_deg {
                return *normal;
            }
        }
        element_normal(incidence_deg, self.airframe.elements[6].dihedral_deg)
    }

    /// The airframe.
    #[must_use]
    pub fn airframe(&self) -> &Airframe {
        &self.airframe
    }

    /// Its mass properties.
    #[must_use]
    pub fn mass_properties(&self) -> &MassProperties {
        &self.mass
    }
}

impl Default for BourgAircraft {
    fn default() -> Self {
        Self::bourg_default()
    }
}
