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


def time_series_views(path) -> list[dict]:
    """Each time-series view of the stored blueprint: origin, name, whether its legend is visible (None: not
    set), and its time axis as (kind, start, end) in ns, kind "CursorRelative" or "Absolute"."""
    reader = RrdReader(path)
    (blueprint,) = reader.blueprints()
    views, legends, axes = {}, {}, {}
    for chunk in reader.stream(store=blueprint):
        batch = chunk.to_record_batch()
        view = "/".join(chunk.entity_path.strip("/").split("/")[:2])
        names = batch.schema.names
        if "ViewBlueprint:class_identifier" in names:
            kind = batch.column("ViewBlueprint:class_identifier").to_pylist()[-1][0]
            if kind == "TimeSeries":
                views[view] = {"origin": batch.column("ViewBlueprint:space_origin").to_pylist()[-1][0],
                               "name": batch.column("ViewBlueprint:display_name").to_pylist()[-1][0]}
        if "PlotLegend:visible" in names:
            legends[view] = batch.column("PlotLegend:visible").to_pylist()[-1][0]
        if "TimeAxis:view_range" in names:
            bounds = batch.column("TimeAxis:view_range").flatten()
            start, end = bounds.field("start"), bounds.field("end")
            code = start.type_codes[len(start) - 1].as_py()
            kind = start.type.field(list(start.type.type_codes).index(code)).name
            axes[view] = (kind, start[-1].as_py(), end[-1].as_py())
    return [dict(v, legend=legends.get(k), axis=axes.get(k)) for k, v in views.items()]
