"""Reading .rrd files back in tests (rerun's RrdReader and pyarrow)."""

import pyarrow as pa
from rerun.chunk import RrdReader


def blueprint_views(path) -> dict:
    """View kind ("3D", "TimeSeries", ...) -> set of origins, from the blueprint stored in the file."""
    reader = RrdReader(path)
    (blueprint,) = reader.blueprints()
    views = {}
    for chunk in reader.stream(store=blueprint):
        batch = chunk.to_record_batch()
        if "ViewBlueprint:class_identifier" in batch.schema.names:
            for kind, origin in zip(batch.column("ViewBlueprint:class_identifier").to_pylist(),
                                    batch.column("ViewBlueprint:space_origin").to_pylist()):
                views.setdefault(kind[0], set()).add(origin[0])
    return views


def rows(path, entity):
    """Time-varying rows of one entity, concatenated over chunks and sorted by sim_time."""
    batches = [c.to_record_batch() for c in RrdReader(path).stream().filter(content=entity, is_static=False)]
    assert batches, f"no data for {entity}"
    table = pa.concat_tables([pa.Table.from_batches([b]) for b in batches], promote_options="default")
    return table.sort_by("sim_time")
