"""Reads an Arrow IPC file with pyarrow and prints what it finds as JSON:
the schema (name, type, nullable per field), the number of record batches
and every column, floats as float.hex() so that the comparison is bit-exact
and nulls as null."""

import json
import sys

import pyarrow as pa
import pyarrow.ipc as ipc

with pa.memory_map(sys.argv[1], "r") as source:
    reader = ipc.open_file(source)
    table = reader.read_all()
    batches = reader.num_record_batches

table.validate(full=True)
out = {
    "batches": batches,
    "schema": [[f.name, str(f.type), f.nullable] for f in table.schema],
    "columns": {},
}
for name in table.column_names:
    values = table.column(name).to_pylist()
    out["columns"][name] = [v.hex() if isinstance(v, float) else v for v in values]
print(json.dumps(out))
