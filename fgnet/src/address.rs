//! FlightGear's UDP endpoints as a user writes them, `HOST:PORT`: where
//! FlightGear listens for native-FDM datagrams (`sim-cli --fg`, Python's
//! `Flight.flightgear_to`), checked strictly before a socket is made.
//!
//! FlightGear 2020.3's native-FDM socket is IPv4 only, so IPv6 is refused up
//! front; a datagram cannot usefully go to the broadcast or the unspecified
//! address, so a *target* naming either is refused with the reason
//! ([`parse_fg_target`]), while the address FlightGear *listens* on may be
//! 0.0.0.0 ([`parse_fg_listen`]).
//!
//! ```
//! use fgnet::address::{parse_fg_target, FgAddressError};
//!
//! let target = parse_fg_target("127.0.0.1:5500")?;
//! assert_eq!((target.host.as_str(), target.port), ("127.0.0.1", 5500));
//! assert_eq!(target.resolve()?.to_string(), "127.0.0.1:5500");
//! assert!(matches!(parse_fg_target("0.0.0.0:5500"), Err(FgAddressError::Unspecified { .. })));
//! assert!(matches!(parse_fg_target("[::1]:5500"), Err(FgAddressError::Ipv6 { .. })));
//! # Ok::<(), FgAddressError>(())
//! ```

use std::fmt;
use std::net::{Ipv4Addr, SocketAddrV4, ToSocketAddrs};
use std::str::FromStr;

use fdm_core::script::Echo;

/// Where interactive runs send packets when no target is given.
pub const DEFAULT_FG: &str = "127.0.0.1:5500";

/// How `HOST:PORT` is written, in messages.
const FORMAT: &str = "expected HOST:PORT (e.g. 127.0.0.1:5500)";

/// Why a FlightGear endpoint was refused. Each message is one line and
/// quotes the user's text through [`Echo`] (control characters escaped,
/// long text cut).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FgAddressError {
    /// `[::1]:5500` or `::1:5500`: FlightGear's native-FDM socket is IPv4 only.
    #[error(
        "`{text}`: IPv6 is not supported (FlightGear's native-FDM socket is IPv4 only); {FORMAT}"
    )]
    Ipv6 {
        /// The text as given (echoed safely in the message).
        text: String,
    },
    /// No `:PORT`.
    #[error("`{text}`: missing port; {FORMAT}")]
    MissingPort {
        /// The text as given.
        text: String,
    },
    /// Nothing before the `:`.
    #[error("`{text}`: missing host; {FORMAT}")]
    MissingHost {
        /// The text as given.
        text: String,
    },
    /// A host whose last label starts with a digit but is not a dotted quad
    /// (`0x7f.0.0.1`, `127.1`, `2130706433`, `017.0.0.1`).
    #[error("`{host}` is not a plain IPv4 address (four decimal numbers 0-255 separated by dots); {FORMAT}")]
    NotPlainIpv4 {
        /// The host part.
        host: String,
    },
    /// Not an RFC 1123 host name.
    #[error("`{host}` is not a host name or IPv4 address; {FORMAT}")]
    NotHostName {
        /// The host part.
        host: String,
    },
    /// Not decimal digits in 1..65535.
    #[error("port `{port}` is not a decimal number in 1..65535; {FORMAT}")]
    BadPort {
        /// The port part.
        port: String,
    },
    /// 255.255.255.255 as a target: the kernel refuses it without
    /// `SO_BROADCAST`, and FlightGear listens on one host anyway.
    #[error("`{ip}` is the broadcast address; give the address of the host FlightGear runs on (127.0.0.1 for this machine)")]
    Broadcast {
        /// The address.
        ip: Ipv4Addr,
    },
    /// 255.255.255.255 as the address FlightGear listens on.
    #[error("`{ip}` is the broadcast address; FlightGear listens on one host's address (or 0.0.0.0 for all)")]
    BroadcastListen {
        /// The address.
        ip: Ipv4Addr,
    },
    /// 0.0.0.0 as a target: no host at all.
    #[error("`{ip}` is the unspecified address (no host); give the address of the host FlightGear runs on (127.0.0.1 for this machine)")]
    Unspecified {
        /// The address.
        ip: Ipv4Addr,
    },
    /// The host name did not resolve.
    #[error("cannot resolve FlightGear host `{host}`: {message}")]
    Resolve {
        /// The host.
        host: String,
        /// The resolver's error.
        message: String,
    },
    /// The host resolved to IPv6 addresses only.
    #[error("FlightGear host `{host}` has no IPv4 address")]
    NoIpv4 {
        /// The host.
        host: String,
    },
    /// The host resolved to the broadcast or unspecified address.
    #[error("FlightGear host `{host}`: {refused}")]
    Resolved {
        /// The host.
        host: String,
        /// Why its address is refused ([`Self::Broadcast`] or [`Self::Unspecified`]).
        refused: Box<FgAddressError>,
    },
}

/// The user's text, safe to print in a one-line message.
fn echo(text: &str) -> String {
    Echo::short(text).to_string()
}

/// A FlightGear native-FDM UDP endpoint as the user wrote it: a host name or IPv4
/// literal and a port. The host is kept as text because `fgfs-command` must print it
/// back exactly (`--native-fdm=socket,in,HZ,HOST,PORT,udp`), while the sender needs
/// the resolved address ([`FgTarget::resolve`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FgTarget {
    /// Host name or dotted IPv4 address (never empty).
    pub host: String,
    /// UDP port (never 0).
    pub port: u16,
}

impl Default for FgTarget {
    fn default() -> Self {
        Self {
            host: "127.0.0.1".to_owned(),
            port: 5500,
        }
    }
}

impl fmt::Display for FgTarget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.host, self.port)
    }
}

/// Parses as [`parse_fg_listen`] (0.0.0.0 allowed); the send path refuses it in
/// [`parse_fg_target`] and again in [`FgTarget::resolve`].
impl FromStr for FgTarget {
    type Err = FgAddressError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_fg_listen(s)
    }
}

/// Parses `--fg HOST:PORT` for sending: [`parse_host_port`], and the address must
/// be one host. The broadcast address (255.255.255.255: the kernel refuses it
/// without SO_BROADCAST, and FlightGear listens on one host anyway) and the
/// unspecified address (0.0.0.0: no host at all) are refused with the reason.
pub fn parse_fg_target(text: &str) -> Result<FgTarget, FgAddressError> {
    let target = parse_host_port(text)?;
    if let Ok(ip) = target.host.parse::<Ipv4Addr>() {
        check_unicast(ip)?;
    }
    Ok(target)
}

/// Parses `fgfs-command --fg HOST:PORT`, the address FlightGear listens on:
/// [`parse_host_port`]; 0.0.0.0 (all interfaces) is allowed there, the
/// broadcast address is not.
pub fn parse_fg_listen(text: &str) -> Result<FgTarget, FgAddressError> {
    let target = parse_host_port(text)?;
    if target
        .host
        .parse::<Ipv4Addr>()
        .is_ok_and(|ip| ip.is_broadcast())
    {
        return Err(FgAddressError::BroadcastListen {
            ip: Ipv4Addr::BROADCAST,
        });
    }
    Ok(target)
}

/// Refuses the addresses a datagram cannot usefully be sent to.
const fn check_unicast(ip: Ipv4Addr) -> Result<(), FgAddressError> {
    if ip.is_broadcast() {
        return Err(FgAddressError::Broadcast { ip });
    }
    if ip.is_unspecified() {
        return Err(FgAddressError::Unspecified { ip });
    }
    Ok(())
}

/// Parses `HOST:PORT` strictly. IPv6 is rejected up front because FlightGear
/// 2020.3's native-FDM socket is IPv4 only, so such a target could never work.
///
/// * HOST is a plain IPv4 dotted quad (four decimal numbers 0-255, no leading
///   zeros) or a host name: dot-separated labels of letters, digits and `-`
///   (1 to 63 characters, not starting or ending with `-`, 253 in all). A host
///   whose last label starts with a digit is taken as an IPv4 address and must be
///   a dotted quad, so the resolver never sees the old forms `0x7f.0.0.1`,
///   `127.1` or `2130706433`. This also keeps the printed fgfs command line safe
///   to paste into a shell.
/// * PORT is decimal digits only (no sign), 1 to 65535.
pub fn parse_host_port(text: &str) -> Result<FgTarget, FgAddressError> {
    if text.starts_with('[') || text.matches(':').count() > 1 {
        return Err(FgAddressError::Ipv6 { text: echo(text) });
    }
    let Some((host, port)) = text.rsplit_once(':') else {
        return Err(FgAddressError::MissingPort { text: echo(text) });
    };
    if host.is_empty() {
        return Err(FgAddressError::MissingHost { text: echo(text) });
    }
    let last_label = host.rsplit('.').next().unwrap_or(host);
    if last_label.starts_with(|c: char| c.is_ascii_digit()) {
        if host.parse::<Ipv4Addr>().is_err() {
            return Err(FgAddressError::NotPlainIpv4 { host: echo(host) });
        }
    } else if !is_host_name(host) {
        return Err(FgAddressError::NotHostName { host: echo(host) });
    }
    let port = match port.parse::<u16>() {
        Ok(p) if p != 0 && port.bytes().all(|b| b.is_ascii_digit()) => p,
        _ => return Err(FgAddressError::BadPort { port: echo(port) }),
    };
    Ok(FgTarget {
        host: host.to_owned(),
        port,
    })
}

/// RFC 1123 host name syntax (letters, digits, hyphens; labels of 1-63).
fn is_host_name(host: &str) -> bool {
    host.len() <= 253
        && host.split('.').all(|label| {
            (1..=63).contains(&label.len())
                && label
                    .bytes()
                    .all(|b| b.is_ascii_alphanumeric() || b == b'-')
                && !label.starts_with('-')
                && !label.ends_with('-')
        })
}

impl FgTarget {
    /// Resolves the host to the first IPv4 address it names.
    ///
    /// # Errors
    /// [`FgAddressError::Resolve`] when the name does not resolve,
    /// [`FgAddressError::NoIpv4`] when it names IPv6 addresses only, and
    /// [`FgAddressError::Resolved`] when it resolves to the broadcast or
    /// unspecified address (see [`parse_fg_target`]).
    pub fn resolve(&self) -> Result<SocketAddrV4, FgAddressError> {
        let addrs = (self.host.as_str(), self.port)
            .to_socket_addrs()
            .map_err(|e| FgAddressError::Resolve {
                host: echo(&self.host),
                message: e.to_string(),
            })?;
        let addr = addrs
            .filter_map(|a| match a {
                std::net::SocketAddr::V4(v4) => Some(v4),
                std::net::SocketAddr::V6(_) => None,
            })
            .next()
            .ok_or_else(|| FgAddressError::NoIpv4 {
                host: echo(&self.host),
            })?;
        check_unicast(*addr.ip()).map_err(|refused| FgAddressError::Resolved {
            host: echo(&self.host),
            refused: Box::new(refused),
        })?;
        Ok(addr)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_default_and_names() {
        assert_eq!(DEFAULT_FG.parse::<FgTarget>(), Ok(FgTarget::default()));
        let t = parse_fg_target("fg-box.local:5501").unwrap();
        assert_eq!((t.host.as_str(), t.port), ("fg-box.local", 5501));
        assert_eq!(t.to_string(), "fg-box.local:5501");
    }

    #[test]
    fn rejects_bad_formats() {
        for bad in [
            "",
            "5500",
            ":5500",
            "host:",
            "host:0",
            "host:65536",
            "host:port",
            "[::1]:5500",
            "::1:5500",
            "a b:1",
            "-x:1",
            "300.1.1.1:5500",
            "1.2.3:5500",
            "host;rm:1",
            "0x7f.0.0.1:5500",
            "127.1:5500",
            "2130706433:5500",
            "017.0.0.1:5500",
            "127.0.0.1:+5500",
            "127.0.0.1:0x15",
            "127.0.0.1: 5500",
            "a..b:5500",
            "a-.b:5500",
            "host.:5500",
            "255.255.255.255:5500",
            "0.0.0.0:5500",
        ] {
            let err = parse_fg_target(bad).expect_err(bad);
            assert!(!err.to_string().contains('\n'));
        }
    }

    #[test]
    fn broadcast_and_unspecified_are_refused_with_the_reason() {
        let err = parse_fg_target("255.255.255.255:5500")
            .unwrap_err()
            .to_string();
        assert!(err.contains("is the broadcast address"), "{err}");
        let err = parse_fg_target("0.0.0.0:5500").unwrap_err().to_string();
        assert!(err.contains("is the unspecified address"), "{err}");
        // FlightGear itself may listen on all interfaces.
        assert_eq!(parse_fg_listen("0.0.0.0:5500").unwrap().host, "0.0.0.0");
        assert!(parse_fg_listen("255.255.255.255:5500").is_err());
        let err = parse_fg_target("0x7f.0.0.1:+5500").unwrap_err().to_string();
        assert!(err.contains("not a plain IPv4 address"), "{err}");
        let err = parse_fg_target("127.0.0.1:+5500").unwrap_err().to_string();
        assert!(err.contains("not a decimal number"), "{err}");
    }

    #[test]
    fn resolves_ipv4_literal_without_dns() {
        let t = parse_fg_target("127.0.0.1:5500").unwrap();
        assert_eq!(
            t.resolve(),
            Ok(SocketAddrV4::new(Ipv4Addr::LOCALHOST, 5500))
        );
    }
}
