//! Shared by the `fgnet_*` integration tests: the field table of docs/fgnetfdm.md §3 (offsets
//! copied from the FGNetFDM v24 layout table, `docs/fgnetfdm.md`, not derived
//! from the crate), with
//! flightgear-python's field names, and bitwise field access.

use fgnet::FgNetFdm;

/// Wire type of one field element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Unsigned 32-bit integer.
    U32,
    /// Signed 32-bit integer.
    I32,
    /// IEEE-754 binary32.
    F32,
    /// IEEE-754 binary64.
    F64,
}

impl Kind {
    /// Size of one element on the wire, bytes.
    pub const fn size(self) -> usize {
        match self {
            Kind::F64 => 8,
            _ => 4,
        }
    }

    /// The kind name the Python helper reports (`fgnet_py_common.py`).
    pub const fn py(self) -> &'static str {
        match self {
            Kind::U32 => "u32",
            Kind::I32 => "i32",
            Kind::F32 => "f32",
            Kind::F64 => "f64",
        }
    }
}

/// One row of that table. Arrays have `len` > 1 and element `i` sits at
/// `offset + i * kind.size()`. Values are passed as raw bits: `to_bits` for
/// floats, the two's-complement `u32` for `warp`.
pub struct Field {
    /// The C header's name, as in docs/fgnetfdm.md and the golden JSON.
    pub name: &'static str,
    /// flightgear-python's `fdm_v24` name.
    pub py: &'static str,
    /// Byte offset of the first element in the datagram.
    pub offset: usize,
    /// Wire type of each element.
    pub kind: Kind,
    /// Number of elements (1 for scalars).
    pub len: usize,
    /// Reads element `i` as its bit pattern.
    pub get: fn(&FgNetFdm, usize) -> u64,
    /// Writes element `i` from a bit pattern.
    pub set: fn(&mut FgNetFdm, usize, u64),
}

impl Field {
    /// Is this one of the three counts the encoder clamps?
    pub fn count_max(&self) -> Option<u64> {
        match self.name {
            "num_engines" | "num_tanks" => Some(4),
            "num_wheels" => Some(3),
            _ => None,
        }
    }

    /// The element's name: the field name, with `[i]` for arrays.
    pub fn element_name(&self, i: usize) -> String {
        if self.len == 1 {
            self.name.to_owned()
        } else {
            format!("{}[{i}]", self.name)
        }
    }
}

macro_rules! to_bits {
    (F64, $e:expr) => {
        $e.to_bits()
    };
    (F32, $e:expr) => {
        u64::from($e.to_bits())
    };
    (U32, $e:expr) => {
        u64::from($e)
    };
    (I32, $e:expr) => {
        u64::from($e as u32)
    };
}

macro_rules! from_bits {
    (F64, $v:expr) => {
        f64::from_bits($v)
    };
    (F32, $v:expr) => {
        f32::from_bits($v as u32)
    };
    (U32, $v:expr) => {
        $v as u32
    };
    (I32, $v:expr) => {
        $v as u32 as i32
    };
}

macro_rules! table {
    ($( $off:literal $kind:ident $name:literal $py:literal $field:ident $([$n:literal])? ;)*) => {
        vec![$( table!(@row $off $kind $name $py $field $([$n])?) ),*]
    };
    (@row $off:literal $kind:ident $name:literal $py:literal $field:ident) => {
        Field {
            name: $name,
            py: $py,
            offset: $off,
            kind: Kind::$kind,
            len: 1,
            get: |f, _| to_bits!($kind, f.$field),
            set: |f, _, v| f.$field = from_bits!($kind, v),
        }
    };
    (@row $off:literal $kind:ident $name:literal $py:literal $field:ident [$n:literal]) => {
        Field {
            name: $name,
            py: $py,
            offset: $off,
            kind: Kind::$kind,
            len: $n,
            get: |f, i| to_bits!($kind, f.$field[i]),
            set: |f, i, v| f.$field[i] = from_bits!($kind, v),
        }
    };
}

/// The §3 table of docs/fgnetfdm.md, in wire order.
pub fn fields() -> Vec<Field> {
    table! {
        0 U32 "version" "version" version;
        4 U32 "padding" "_padding" padding;
        8 F64 "longitude" "lon_rad" longitude;
        16 F64 "latitude" "lat_rad" latitude;
        24 F64 "altitude" "alt_m" altitude;
        32 F32 "agl" "agl_m" agl;
        36 F32 "phi" "phi_rad" phi;
        40 F32 "theta" "theta_rad" theta;
        44 F32 "psi" "psi_rad" psi;
        48 F32 "alpha" "alpha_rad" alpha;
        52 F32 "beta" "beta_rad" beta;
        56 F32 "phidot" "phidot_rad_per_s" phidot;
        60 F32 "thetadot" "thetadot_rad_per_s" thetadot;
        64 F32 "psidot" "psidot_rad_per_s" psidot;
        68 F32 "vcas" "vcas" vcas;
        72 F32 "climb_rate" "climb_rate_ft_per_s" climb_rate;
        76 F32 "v_north" "v_north_ft_per_s" v_north;
        80 F32 "v_east" "v_east_ft_per_s" v_east;
        84 F32 "v_down" "v_down_ft_per_s" v_down;
        88 F32 "v_body_u" "v_body_u" v_body_u;
        92 F32 "v_body_v" "v_body_v" v_body_v;
        96 F32 "v_body_w" "v_body_w" v_body_w;
        100 F32 "A_X_pilot" "A_X_pilot_ft_per_s_per_s" a_x_pilot;
        104 F32 "A_Y_pilot" "A_Y_pilot_ft_per_s_per_s" a_y_pilot;
        108 F32 "A_Z_pilot" "A_Z_pilot_ft_per_s_per_s" a_z_pilot;
        112 F32 "stall_warning" "stall_warning" stall_warning;
        116 F32 "slip_deg" "slip_deg" slip_deg;
        120 U32 "num_engines" "num_engines" num_engines;
        124 U32 "eng_state" "eng_state" eng_state[4];
        140 F32 "rpm" "rpm" rpm[4];
        156 F32 "fuel_flow" "fuel_flow_gal_per_hr" fuel_flow[4];
        172 F32 "fuel_px" "fuel_px_psi" fuel_px[4];
        188 F32 "egt" "egt_deg_F" egt[4];
        204 F32 "cht" "cht_deg_F" cht[4];
        220 F32 "mp_osi" "mp_osi" mp_osi[4];
        236 F32 "tit" "tit" tit[4];
        252 F32 "oil_temp" "oil_temp_deg_F" oil_temp[4];
        268 F32 "oil_px" "oil_px_psi" oil_px[4];
        284 U32 "num_tanks" "num_tanks" num_tanks;
        288 F32 "fuel_quantity" "fuel_quantity" fuel_quantity[4];
        304 U32 "num_wheels" "num_wheels" num_wheels;
        308 U32 "wow" "wow" wow[3];
        320 F32 "gear_pos" "gear_pos" gear_pos[3];
        332 F32 "gear_steer" "gear_steer" gear_steer[3];
        344 F32 "gear_compression" "gear_compression" gear_compression[3];
        356 U32 "cur_time" "cur_time_s" cur_time;
        360 I32 "warp" "warp_s" warp;
        364 F32 "visibility" "visibility_m" visibility;
        368 F32 "elevator" "elevator" elevator;
        372 F32 "elevator_trim_tab" "elevator_trim_tab" elevator_trim_tab;
        376 F32 "left_flap" "left_flap" left_flap;
        380 F32 "right_flap" "right_flap" right_flap;
        384 F32 "left_aileron" "left_aileron" left_aileron;
        388 F32 "right_aileron" "right_aileron" right_aileron;
        392 F32 "rudder" "rudder" rudder;
        396 F32 "nose_wheel" "nose_wheel" nose_wheel;
        400 F32 "speedbrake" "speedbrake" speedbrake;
        404 F32 "spoilers" "spoilers" spoilers;
    }
}

/// Every field element as (name, bits), in wire order.
pub fn element_bits(fdm: &FgNetFdm) -> Vec<(String, u64)> {
    let mut out = Vec::new();
    for f in fields() {
        for i in 0..f.len {
            out.push((f.element_name(i), (f.get)(fdm, i)));
        }
    }
    out
}

/// Builds a struct from raw bits, one per field element in wire order.
pub fn from_element_bits(bits: &[u64]) -> FgNetFdm {
    let mut fdm = FgNetFdm::new();
    let mut it = bits.iter();
    for f in fields() {
        for i in 0..f.len {
            let v = *it.next().expect("one value per field element");
            (f.set)(&mut fdm, i, v);
        }
    }
    assert!(it.next().is_none(), "more values than field elements");
    fdm
}

/// Number of field elements (scalars plus array entries).
pub fn element_count() -> usize {
    fields().iter().map(|f| f.len).sum()
}

/// Asserts that two structs are equal bit for bit (NaN payloads included),
/// naming the first field that differs.
pub fn assert_bitwise_eq(actual: &FgNetFdm, expected: &FgNetFdm, context: &str) {
    for ((name, a), (_, e)) in element_bits(actual).into_iter().zip(element_bits(expected)) {
        assert_eq!(
            a, e,
            "{context}: field {name} differs: bits {a:#x}, expected {e:#x}"
        );
    }
}
