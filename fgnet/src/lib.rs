//! FlightGear "native FDM" datagrams (FGNetFDM, protocol version 24): the
//! 408-byte big-endian struct FlightGear 2020.3 accepts on
//! `--native-fdm=socket,in,...,udp`, its encoder and decoder, and a UDP sender.
