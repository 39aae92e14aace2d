//! The per-run table as an Arrow IPC file (`runs.arrow`, Arrow columnar
//! format version 5, the "file" form that `pyarrow.ipc.open_file`,
//! `pandas.read_feather` and `polars.read_ipc` read directly): `run` as
//! UInt64, `status` as Utf8, each measure as a nullable Float64 (null where
//! the measure does not apply), each drawn input (`input.KEY`) as a Float64,
//! and `fingerprint` as a nullable Utf8 (`0x` and 16 hex digits, as in
//! `runs.csv`; null for a refused start). One record batch per
//! [`ArrowWriter::write`].
//!
//! Written by hand, without the arrow crates: the format needs only a few
//! flatbuffer tables (Schema, Field, RecordBatch, Footer), built here front
//! to back (every offset points forward). pyarrow reads the files back in
//! the workspace's interop test (`fdm-study/tests/pyarrow_interop.rs`).

use std::io::{self, Write};

use crate::table::RunTable;

/// One value of a flatbuffer table field.
enum Slot {
    Bool(bool),
    I16(i16),
    I32(i32),
    I64(i64),
    U8(u8),
    Child(Node),
}

/// A flatbuffer object.
enum Node {
    /// A table: (field id, value).
    Table(Vec<(u16, Slot)>),
    Str(String),
    /// A vector of tables.
    Tables(Vec<Node>),
    /// A vector of 8-byte-aligned structs, as little-endian bytes.
    Structs {
        count: u32,
        bytes: Vec<u8>,
    },
}

fn pad_to(buf: &mut Vec<u8>, align: usize) {
    while !buf.len().is_multiple_of(align) {
        buf.push(0);
    }
}

fn patch_u32(buf: &mut [u8], at: usize, value: u32) {
    buf[at..at + 4].copy_from_slice(&value.to_le_bytes());
}

fn offset(from: usize, to: usize) -> u32 {
    u32::try_from(to - from).unwrap_or(u32::MAX)
}

/// Writes `node` at the end of `buf` (whose start is 8-aligned in the file)
/// and returns its position (where an offset to it points).
fn emit(buf: &mut Vec<u8>, node: &Node) -> usize {
    match node {
        Node::Str(s) => {
            pad_to(buf, 4);
            let at = buf.len();
            buf.extend_from_slice(&u32::try_from(s.len()).unwrap_or(0).to_le_bytes());
            buf.extend_from_slice(s.as_bytes());
            buf.push(0);
            at
        }
        Node::Structs { count, bytes } => {
            while !(buf.len() + 4).is_multiple_of(8) {
                buf.push(0);
            }
            let at = buf.len();
            buf.extend_from_slice(&count.to_le_bytes());
            buf.extend_from_slice(bytes);
            at
        }
        Node::Tables(items) => {
            pad_to(buf, 4);
            let at = buf.len();
            buf.extend_from_slice(&u32::try_from(items.len()).unwrap_or(0).to_le_bytes());
            let slots = buf.len();
            buf.resize(slots + 4 * items.len(), 0);
            for (i, item) in items.iter().enumerate() {
                let child = emit(buf, item);
                patch_u32(buf, slots + 4 * i, offset(slots + 4 * i, child));
            }
            at
        }
        Node::Table(fields) => {
            let slots = fields
                .iter()
                .map(|(id, _)| usize::from(*id) + 1)
                .max()
                .unwrap_or(0);
            let vtable_len = 4 + 2 * slots;
            // The vtable right before the table; the table 8-aligned.
            pad_to(buf, 2);
            while !(buf.len() + vtable_len).is_multiple_of(8) {
                buf.extend_from_slice(&[0, 0]);
            }
            let vtable = buf.len();
            let table = vtable + vtable_len;
            // Inline layout: the soffset, then fields by decreasing size.
            let size = |s: &Slot| -> usize {
                match s {
                    Slot::Bool(_) | Slot::U8(_) => 1,
                    Slot::I16(_) => 2,
                    Slot::I32(_) | Slot::Child(_) => 4,
                    Slot::I64(_) => 8,
                }
            };
            let mut order: Vec<usize> = (0..fields.len()).collect();
            order.sort_by_key(|&i| std::cmp::Reverse(size(&fields[i].1)));
            let mut at = vec![0usize; fields.len()];
            let mut end: usize = 4;
            for &i in &order {
                let s = size(&fields[i].1);
                end = end.div_ceil(s) * s;
                at[i] = end;
                end += s;
            }
            let table_len = end.div_ceil(4) * 4;
            buf.resize(table + table_len, 0);
            let mut vt = vec![0u8; vtable_len];
            vt[0..2].copy_from_slice(&u16::try_from(vtable_len).unwrap_or(0).to_le_bytes());
            vt[2..4].copy_from_slice(&u16::try_from(table_len).unwrap_or(0).to_le_bytes());
            for (i, (id, _)) in fields.iter().enumerate() {
                let slot = 4 + 2 * usize::from(*id);
                vt[slot..slot + 2]
                    .copy_from_slice(&u16::try_from(at[i]).unwrap_or(0).to_le_bytes());
            }
            buf[vtable..table].copy_from_slice(&vt);
            let soffset = i32::try_from(table - vtable).unwrap_or(0);
            buf[table..table + 4].copy_from_slice(&soffset.to_le_bytes());
            for (i, (_, slot)) in fields.iter().enumerate() {
                let p = table + at[i];
                match slot {
                    Slot::Bool(v) => buf[p] = u8::from(*v),
                    Slot::U8(v) => buf[p] = *v,
                    Slot::I16(v) => buf[p..p + 2].copy_from_slice(&v.to_le_bytes()),
                    Slot::I32(v) => buf[p..p + 4].copy_from_slice(&v.to_le_bytes()),
                    Slot::I64(v) => buf[p..p + 8].copy_from_slice(&v.to_le_bytes()),
                    Slot::Child(_) => {}
                }
            }
            for (i, (_, slot)) in fields.iter().enumerate() {
                if let Slot::Child(child) = slot {
                    let p = table + at[i];
                    let c = emit(buf, child);
                    patch_u32(buf, p, offset(p, c));
                }
            }
            table
        }
    }
}

/// A finished flatbuffer with `root` as its root table, padded to 8 bytes.
fn flatbuffer(root: &Node) -> Vec<u8> {
    let mut buf = vec![0u8; 4];
    let at = emit(&mut buf, root);
    patch_u32(&mut buf, 0, offset(0, at));
    pad_to(&mut buf, 8);
    buf
}

/// Arrow's MetadataVersion V5.
const V5: i16 = 4;
/// MessageHeader union: Schema.
const HEADER_SCHEMA: u8 = 1;
/// MessageHeader union: RecordBatch.
const HEADER_RECORD_BATCH: u8 = 3;
/// Type union: Int, FloatingPoint, Utf8.
const TYPE_INT: u8 = 2;
const TYPE_FLOAT: u8 = 3;
const TYPE_UTF8: u8 = 5;
/// FloatingPoint precision DOUBLE.
const DOUBLE: i16 = 2;
const MAGIC: &[u8; 6] = b"ARROW1";

fn field(name: &str, nullable: bool, type_id: u8, ty: Node) -> Node {
    Node::Table(vec![
        (0, Slot::Child(Node::Str(name.to_owned()))),
        (1, Slot::Bool(nullable)),
        (2, Slot::U8(type_id)),
        (3, Slot::Child(ty)),
        (5, Slot::Child(Node::Tables(Vec::new()))),
    ])
}

fn schema(measures: &[String], inputs: &[String]) -> Node {
    let mut fields = vec![
        field(
            "run",
            false,
            TYPE_INT,
            Node::Table(vec![(0, Slot::I32(64)), (1, Slot::Bool(false))]),
        ),
        field("status", false, TYPE_UTF8, Node::Table(Vec::new())),
    ];
    for name in measures {
        fields.push(field(
            name,
            true,
            TYPE_FLOAT,
            Node::Table(vec![(0, Slot::I16(DOUBLE))]),
        ));
    }
    for name in inputs {
        fields.push(field(
            name,
            false,
            TYPE_FLOAT,
            Node::Table(vec![(0, Slot::I16(DOUBLE))]),
        ));
    }
    fields.push(field(
        "fingerprint",
        true,
        TYPE_UTF8,
        Node::Table(Vec::new()),
    ));
    // Endianness Little (0, the default) and the fields.
    Node::Table(vec![(1, Slot::Child(Node::Tables(fields)))])
}

fn message(header_type: u8, header: Node, body_len: u64) -> Vec<u8> {
    flatbuffer(&Node::Table(vec![
        (0, Slot::I16(V5)),
        (1, Slot::U8(header_type)),
        (2, Slot::Child(header)),
        (3, Slot::I64(i64::try_from(body_len).unwrap_or(i64::MAX))),
    ]))
}

fn le_i64(out: &mut Vec<u8>, v: usize) {
    out.extend_from_slice(&i64::try_from(v).unwrap_or(i64::MAX).to_le_bytes());
}

/// Writes an Arrow IPC file of run tables, batch by batch.
#[derive(Debug)]
pub struct ArrowWriter<W: Write> {
    out: W,
    measures: Vec<String>,
    inputs: Vec<String>,
    position: u64,
    /// (offset, metadata length, body length) of each record batch.
    blocks: Vec<(u64, u32, u64)>,
}

impl<W: Write> ArrowWriter<W> {
    /// Starts the file for tables with `columns`' columns (an empty table
    /// will do, e.g. [`crate::Study::empty_table`]): the magic and the
    /// schema (`run`, `status`, the measures, the inputs, `fingerprint`).
    ///
    /// # Errors
    /// The writer's.
    pub fn new(out: W, columns: &RunTable) -> io::Result<Self> {
        let mut writer = Self {
            out,
            measures: columns.measures.iter().map(|(n, _)| n.clone()).collect(),
            inputs: columns.inputs.iter().map(|(n, _)| n.clone()).collect(),
            position: 0,
            blocks: Vec::new(),
        };
        writer.put(b"ARROW1\0\0")?;
        let meta = message(HEADER_SCHEMA, schema(&writer.measures, &writer.inputs), 0);
        writer.put_message(&meta)?;
        Ok(writer)
    }

    fn put(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.out.write_all(bytes)?;
        self.position += bytes.len() as u64;
        Ok(())
    }

    /// The continuation marker, the metadata length and the metadata;
    /// returns the bytes written.
    fn put_message(&mut self, meta: &[u8]) -> io::Result<u32> {
        let len = u32::try_from(meta.len()).unwrap_or(u32::MAX);
        self.put(&0xFFFF_FFFFu32.to_le_bytes())?;
        self.put(&len.to_le_bytes())?;
        self.put(meta)?;
        Ok(len + 8)
    }

    /// Appends `table`'s rows as one record batch.
    ///
    /// # Errors
    /// The writer's; `InvalidInput` when the table's measures or inputs
    /// are not the file's, or a column's length is not the table's.
    pub fn write(&mut self, table: &RunTable) -> io::Result<()> {
        let names: Vec<&String> = table.measures.iter().map(|(n, _)| n).collect();
        let inputs: Vec<&String> = table.inputs.iter().map(|(n, _)| n).collect();
        if names != self.measures.iter().collect::<Vec<_>>()
            || inputs != self.inputs.iter().collect::<Vec<_>>()
        {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "the table's measures or inputs are not the file's",
            ));
        }
        let rows = table.len();
        if table.fingerprint.len() != rows
            || table.measures.iter().any(|(_, c)| c.len() != rows)
            || table.inputs.iter().any(|(_, c)| c.len() != rows)
        {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "the table's columns differ in length",
            ));
        }
        let mut body = Vec::new();
        let mut buffers = Vec::new();
        let mut nodes = Vec::new();
        let mut add = |body: &mut Vec<u8>, bytes: &[u8]| {
            let at = body.len();
            body.extend_from_slice(bytes);
            pad_to(body, 8);
            le_i64(&mut buffers, at);
            le_i64(&mut buffers, bytes.len());
        };
        // run: no validity buffer, u64 values.
        le_i64(&mut nodes, rows);
        le_i64(&mut nodes, 0);
        add(&mut body, &[]);
        let runs: Vec<u8> = table.run.iter().flat_map(|r| r.to_le_bytes()).collect();
        add(&mut body, &runs);
        // status: offsets and UTF-8 bytes.
        le_i64(&mut nodes, rows);
        le_i64(&mut nodes, 0);
        add(&mut body, &[]);
        let mut offsets = Vec::with_capacity(4 * (rows + 1));
        let mut text = Vec::new();
        offsets.extend_from_slice(&0i32.to_le_bytes());
        for status in &table.status {
            text.extend_from_slice(status.code().as_bytes());
            offsets.extend_from_slice(&i32::try_from(text.len()).unwrap_or(i32::MAX).to_le_bytes());
        }
        add(&mut body, &offsets);
        add(&mut body, &text);
        // measures: validity bitmap (1 = value) and f64 values (0 for nulls).
        for (_, column) in &table.measures {
            let nulls = column.iter().filter(|v| v.is_none()).count();
            le_i64(&mut nodes, rows);
            le_i64(&mut nodes, nulls);
            if nulls == 0 {
                add(&mut body, &[]);
            } else {
                let mut bits = vec![0u8; rows.div_ceil(8)];
                for (i, v) in column.iter().enumerate() {
                    if v.is_some() {
                        bits[i / 8] |= 1 << (i % 8);
                    }
                }
                add(&mut body, &bits);
            }
            let values: Vec<u8> = column
                .iter()
                .flat_map(|v| v.unwrap_or(0.0).to_le_bytes())
                .collect();
            add(&mut body, &values);
        }
        // inputs: no validity buffer, f64 values.
        for (_, column) in &table.inputs {
            le_i64(&mut nodes, rows);
            le_i64(&mut nodes, 0);
            add(&mut body, &[]);
            let values: Vec<u8> = column.iter().flat_map(|v| v.to_le_bytes()).collect();
            add(&mut body, &values);
        }
        // fingerprint: validity bitmap, offsets and UTF-8 bytes.
        let nulls = table.fingerprint.iter().filter(|f| f.is_none()).count();
        le_i64(&mut nodes, rows);
        le_i64(&mut nodes, nulls);
        if nulls == 0 {
            add(&mut body, &[]);
        } else {
            let mut bits = vec![0u8; rows.div_ceil(8)];
            for (i, f) in table.fingerprint.iter().enumerate() {
                if f.is_some() {
                    bits[i / 8] |= 1 << (i % 8);
                }
            }
            add(&mut body, &bits);
        }
        let mut offsets = Vec::with_capacity(4 * (rows + 1));
        let mut text = Vec::new();
        offsets.extend_from_slice(&0i32.to_le_bytes());
        for f in &table.fingerprint {
            if let Some(f) = f {
                text.extend_from_slice(crate::table::fingerprint_text(*f).as_bytes());
            }
            offsets.extend_from_slice(&i32::try_from(text.len()).unwrap_or(i32::MAX).to_le_bytes());
        }
        add(&mut body, &offsets);
        add(&mut body, &text);
        let node_count = u32::try_from(nodes.len() / 16).unwrap_or(0);
        let buffer_count = u32::try_from(buffers.len() / 16).unwrap_or(0);
        let batch = Node::Table(vec![
            (0, Slot::I64(i64::try_from(rows).unwrap_or(i64::MAX))),
            (
                1,
                Slot::Child(Node::Structs {
                    count: node_count,
                    bytes: nodes,
                }),
            ),
            (
                2,
                Slot::Child(Node::Structs {
                    count: buffer_count,
                    bytes: buffers,
                }),
            ),
        ]);
        let meta = message(HEADER_RECORD_BATCH, batch, body.len() as u64);
        let at = self.position;
        let meta_len = self.put_message(&meta)?;
        self.put(&body)?;
        self.blocks.push((at, meta_len, body.len() as u64));
        Ok(())
    }

    /// Ends the file (end-of-stream marker, footer, magic) and returns the
    /// writer.
    ///
    /// # Errors
    /// The writer's.
    pub fn finish(mut self) -> io::Result<W> {
        self.put(&0xFFFF_FFFFu32.to_le_bytes())?;
        self.put(&0u32.to_le_bytes())?;
        let mut blocks = Vec::new();
        for &(offset, meta, body) in &self.blocks {
            blocks.extend_from_slice(&i64::try_from(offset).unwrap_or(i64::MAX).to_le_bytes());
            blocks.extend_from_slice(&i32::try_from(meta).unwrap_or(i32::MAX).to_le_bytes());
            blocks.extend_from_slice(&[0; 4]);
            blocks.extend_from_slice(&i64::try_from(body).unwrap_or(i64::MAX).to_le_bytes());
        }
        let footer = flatbuffer(&Node::Table(vec![
            (0, Slot::I16(V5)),
            (1, Slot::Child(schema(&self.measures, &self.inputs))),
            (
                3,
                Slot::Child(Node::Structs {
                    count: u32::try_from(self.blocks.len()).unwrap_or(0),
                    bytes: blocks,
                }),
            ),
        ]));
        self.put(&footer)?;
        let len = u32::try_from(footer.len()).unwrap_or(u32::MAX);
        self.put(&len.to_le_bytes())?;
        self.put(MAGIC)?;
        self.out.flush()?;
        Ok(self.out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::table::RunStatus;
    use fdm_core::model::FlightStatus;

    /// A vector of structs is placed so that its structs, after the 4-byte
    /// count, start 8-aligned (the flatbuffer rule for 8-byte structs),
    /// from any length of what comes before it, with at most 7 bytes of
    /// padding.
    #[test]
    fn a_vector_of_structs_starts_its_structs_8_aligned() {
        for before in 4..24 {
            let mut buf = vec![0xaa; before];
            let node = Node::Structs {
                count: 1,
                bytes: vec![1; 16],
            };
            let at = emit(&mut buf, &node);
            assert_eq!((at + 4) % 8, 0, "{before}");
            assert!(at >= before && at - before < 8, "{before}: {at}");
            assert_eq!(buf[at..at + 4], 1u32.to_le_bytes());
            assert_eq!(buf.len(), at + 4 + 16);
        }
    }

    /// One run of a table with measure `a` and input `input.x`.
    fn one_row() -> RunTable {
        RunTable {
            run: vec![0],
            status: vec![RunStatus::Flown(FlightStatus::Airborne)],
            frames: vec![1],
            measures: vec![("a".into(), vec![Some(1.0)])],
            inputs: vec![("input.x".into(), vec![2.0])],
            fingerprint: vec![Some(3)],
        }
    }

    /// A batch whose measures or inputs are not the file's, or whose
    /// columns differ in length (each column alone), is refused, and
    /// nothing of it is written.
    #[test]
    fn a_table_unlike_the_files_columns_is_refused() {
        let mut writer = ArrowWriter::new(Vec::new(), &one_row()).unwrap();
        writer.write(&one_row()).unwrap();
        let written = writer.out.len();
        let mut other_measure = one_row();
        other_measure.measures[0].0 = "b".into();
        let mut other_input = one_row();
        other_input.inputs[0].0 = "input.y".into();
        let mut short_fingerprint = one_row();
        short_fingerprint.fingerprint.clear();
        let mut short_measure = one_row();
        short_measure.measures[0].1.clear();
        let mut short_input = one_row();
        short_input.inputs[0].1.clear();
        for (table, message) in [
            (
                other_measure,
                "the table's measures or inputs are not the file's",
            ),
            (
                other_input,
                "the table's measures or inputs are not the file's",
            ),
            (short_fingerprint, "the table's columns differ in length"),
            (short_measure, "the table's columns differ in length"),
            (short_input, "the table's columns differ in length"),
        ] {
            let e = writer.write(&table).unwrap_err();
            assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
            assert_eq!(e.to_string(), message);
            assert_eq!(writer.out.len(), written);
        }
    }
}
