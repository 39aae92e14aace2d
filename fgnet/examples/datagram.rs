//! One FlightGear native-FDM datagram from start to finish: fly Palmer's
//! Cessna for 20 s with `fdm-core`, map its view to FlightGear's fields
//! (`fgnet::bridge::display`), encode the 408 bytes, decode them back, see
//! what the decoder says about a corrupted copy, and send the datagram over
//! UDP to 127.0.0.1.
//!
//! `cargo run -p fgnet --example datagram` sends to a socket of its own on
//! 127.0.0.1 and checks what arrives. With FlightGear running (see
//! `sim-cli fgfs-command palmer`), `cargo run -p fgnet --example datagram --
//! 127.0.0.1:5500` sends it there instead, and FlightGear puts the Cessna
//! where the datagram says.

use std::error::Error;
use std::net::UdpSocket;
use std::time::Duration;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::Model;
use fdm_core::palmer::{Palmer, PalmerAction};
use fgnet::{DecodeError, FgNetFdm, SendOutcome, Sender, DATAGRAM_LEN};

/// Flies Palmer's Cessna for `seconds` at 30 frames per second, full throttle
/// and 5° angle of attack, and returns its datagram.
fn cessna_datagram(seconds: u32) -> FgNetFdm {
    let aircraft = Palmer::default_aircraft();
    let mut controls = Palmer::initial_controls();
    for action in [
        [PalmerAction::ThrottleUp; 20].as_slice(),
        &[PalmerAction::AlphaUp; 5],
    ]
    .concat()
    {
        controls = Palmer::apply(&aircraft, controls, action);
    }
    let mut state = Palmer::initial_state();
    let dt = Palmer::time_step(30.0);
    for _ in 0..seconds * 30 {
        state = Palmer::step(&aircraft, &controls, &state, dt);
    }
    let view = Palmer::view(&aircraft, &controls, &state);
    // The model's earth frame placed at the default origin (Wright-Patterson AFB).
    fgnet::bridge::display(&view, &GeodeticOrigin::default()).packet
}

fn main() -> Result<(), Box<dyn Error>> {
    let fdm = cessna_datagram(20);
    println!(
        "Cessna after 20 s: lat {:.6} lon {:.6} deg, alt {:.1} m, pitch {:.2} deg, {:.1} kt",
        fdm.latitude.to_degrees(),
        fdm.longitude.to_degrees(),
        fdm.altitude,
        f64::from(fdm.theta).to_degrees(),
        fdm.vcas,
    );

    // Encode: 408 big-endian bytes, version 24 first.
    let bytes: [u8; DATAGRAM_LEN] = fdm.encode();
    let head: Vec<String> = bytes[..16].iter().map(|b| format!("{b:02x}")).collect();
    println!("{} bytes: {} ...", bytes.len(), head.join(" "));

    // Decode: the same fields, bit for bit.
    let decoded = FgNetFdm::decode(&bytes)?;
    if decoded != fdm {
        return Err("the decoded datagram differs from the encoded one".into());
    }

    // The decoder refuses what FlightGear would refuse, with a reason.
    let mut little_endian = bytes;
    little_endian[..4].copy_from_slice(&24_u32.to_le_bytes());
    match FgNetFdm::decode(&little_endian) {
        Err(e @ DecodeError::WrongVersion { .. }) => println!("a corrupted copy: {e}"),
        other => return Err(format!("expected a version error, got {other:?}").into()),
    }
    if let Err(e) = FgNetFdm::decode(&bytes[..400]) {
        println!("a truncated one: {e}");
    }

    // Send it. By default to a socket of our own on 127.0.0.1, so we can
    // check what arrives; with an argument, to that HOST:PORT (FlightGear).
    match std::env::args().nth(1) {
        Some(target) => {
            let mut sender = Sender::connect(&target)?;
            match sender.send(&fdm) {
                SendOutcome::Sent => println!("sent to {}", sender.peer()),
                SendOutcome::FirstFailure(e) => println!("sending to {target} failed: {e}"),
                SendOutcome::Failed => println!("sending to {target} failed"),
            }
        }
        None => {
            let receiver = UdpSocket::bind("127.0.0.1:0")?;
            receiver.set_read_timeout(Some(Duration::from_secs(5)))?;
            let mut sender = Sender::connect(&receiver.local_addr()?.to_string())?;
            if let SendOutcome::FirstFailure(e) = sender.send(&fdm) {
                return Err(e.into());
            }
            let mut buf = [0_u8; 1024];
            let (len, from) = receiver.recv_from(&mut buf)?;
            let received = FgNetFdm::decode(&buf[..len])?;
            if received != fdm {
                return Err("the received datagram differs from the sent one".into());
            }
            println!(
                "sent {} datagram(s) from {from} to {}: {len} bytes arrived and decode to the same fields",
                sender.stats().sent,
                sender.peer()
            );
        }
    }
    Ok(())
}
