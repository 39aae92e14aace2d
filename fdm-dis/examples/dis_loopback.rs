//! Two aircraft on a DIS exercise over UDP on 127.0.0.1: a Cessna 172 flying
//! straight and level and Bourg's aircraft flying a steady turn, 60 s at
//! 60 Hz, each with its own dead-reckoning model. A listener on another
//! loopback socket counts what arrives and prints each entity's last state.
//!
//! Run: `cargo run -p fdm-dis --example dis_loopback [-- --v6] [-- --fpw]`.

use std::net::UdpSocket;
use std::time::Duration;

use fdm_dis::geodesy::{ecef_to_geodetic, geodetic_to_ecef, Attitude, Geodetic};
use fdm_dis::{
    ned_to_ecef_rotation, AircraftKind, AircraftState, DisVersion, DrAlgorithm, DrThresholds,
    EntityConfig, EntityIdentity, EntityPublisher, Listener, Marking, UdpSender,
};
use nalgebra::Vector3;

const ORIGIN: Geodetic = Geodetic {
    lat_deg: 39.8264,
    lon_deg: -84.0483,
    alt_m: 1000.0,
};

/// Straight north at `v` m/s from the origin, built in the origin's tangent
/// plane and converted to geodetic, so position and velocity agree.
fn straight(t: f64, v: f64) -> AircraftState {
    let c = ned_to_ecef_rotation(ORIGIN.lat_deg, ORIGIN.lon_deg);
    let p = geodetic_to_ecef(ORIGIN) + c * Vector3::new(v * t, 0.0, 0.0);
    let here = ecef_to_geodetic(p);
    // Origin-NED components to local-NED components at `here`.
    let to_local = ned_to_ecef_rotation(here.lat_deg, here.lon_deg).transpose() * c;
    let c_b = Attitude {
        heading_deg: 0.0,
        pitch_deg: 2.0,
        roll_deg: 0.0,
    }
    .body_to_ned();
    AircraftState::new(
        t,
        here,
        Attitude::from_body_to_ned(&(to_local * c_b)),
        to_local * Vector3::new(v, 0.0, 0.0),
    )
}

/// A level right turn at `v` m/s and `bank_deg`, starting at the origin.
fn turn(t: f64, v: f64, bank_deg: f64) -> AircraftState {
    let w = 9.806_65 * bank_deg.to_radians().tan() / v;
    let r = v / w;
    let psi = w * t;
    let c = ned_to_ecef_rotation(ORIGIN.lat_deg, ORIGIN.lon_deg);
    let p = geodetic_to_ecef(ORIGIN) + c * Vector3::new(r * psi.sin(), r * (1.0 - psi.cos()), 0.0);
    let here = ecef_to_geodetic(p);
    let to_local = ned_to_ecef_rotation(here.lat_deg, here.lon_deg).transpose() * c;
    let c_b = Attitude {
        heading_deg: psi.to_degrees(),
        pitch_deg: 0.0,
        roll_deg: bank_deg,
    }
    .body_to_ned();
    let mut s = AircraftState::new(
        t,
        here,
        Attitude::from_body_to_ned(&(to_local * c_b)),
        to_local * Vector3::new(v * psi.cos(), v * psi.sin(), 0.0),
    );
    s.angular_velocity_body_rad_s = Some(c_b.transpose() * Vector3::new(0.0, 0.0, w));
    s.acceleration_ned_m_s2 =
        Some(to_local * Vector3::new(-v * w * psi.sin(), v * w * psi.cos(), 0.0));
    s
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let version = if args.iter().any(|a| a == "--v6") {
        DisVersion::V6
    } else {
        DisVersion::V7
    };
    let algorithm = if args.iter().any(|a| a == "--fpw") {
        DrAlgorithm::Fpw
    } else {
        DrAlgorithm::Rvw
    };

    let rx = UdpSocket::bind("127.0.0.1:0")?;
    rx.set_read_timeout(Some(Duration::from_millis(200)))?;
    let tx = UdpSender::new(rx.local_addr()?, false)?;

    let mut pubs = Vec::new();
    for (n, kind, marking) in [
        (1, AircraftKind::CESSNA_172_SKYHAWK, "N172SP"),
        (2, AircraftKind::SMALL_CIVIL_FIXED_WING, "BOURG"),
    ] {
        let mut c = EntityConfig::new(
            EntityIdentity::new(10, 20, n)?,
            kind,
            Marking::new(marking)?,
        );
        c.version = version;
        c.dr_algorithm = algorithm;
        pubs.push(EntityPublisher::new(c, DrThresholds::default())?);
    }

    let mut listener = Listener::new();
    let mut buf = [0u8; 2048];
    let frames = 60 * 60;
    for k in 0..=frames {
        let t = f64::from(k) / 60.0;
        let states = [straight(t, 55.0), turn(t, 60.0, 30.0)];
        for (p, s) in pubs.iter_mut().zip(&states) {
            if let Some(due) = p.update(s)? {
                tx.send(due.bytes)?;
                let n = rx.recv(&mut buf)?;
                if let Err(e) = listener.ingest(&buf[..n]) {
                    eprintln!("malformed datagram: {e}");
                }
            }
        }
    }

    println!("{frames} frames at 60 Hz, DIS {version:?}, {algorithm:?}");
    for p in &pubs {
        let c = p.counts();
        println!(
            "  {} {:>7}: {:>4} PDUs (first {}, position {}, orientation {}, heartbeat {})",
            p.config().id,
            p.config().marking.as_str(),
            c.sent,
            c.first_or_reset,
            c.position,
            c.orientation,
            c.heartbeat
        );
    }
    let s = listener.stats();
    println!(
        "listener: {} datagrams, {} bytes, {} PDUs, {} malformed, {} entities",
        s.datagrams,
        s.bytes,
        s.pdus,
        s.malformed_datagrams,
        listener.entity_count()
    );
    for e in listener.entities() {
        println!(
            "  {} {:<7} lat {:.6} lon {:.6} h {:.1} m  hdg {:.2} pitch {:.2} roll {:.2}",
            e.id,
            e.marking,
            e.position.lat_deg,
            e.position.lon_deg,
            e.position.alt_m,
            e.attitude.heading_deg,
            e.attitude.pitch_deg,
            e.attitude.roll_deg
        );
    }
    Ok(())
}
