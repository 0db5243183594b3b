"""The notebook API in one sitting: an axle, Hopf points of both models at a pressure pair, a cycle branch, a
simulation of each model, the multibody model at full fidelity and both models' stability margins.

Run it as a script (``.venv/bin/python docs/examples/notebook.py``) or cell by cell in a notebook, where every
result renders as an HTML table.  Inputs in km/h, bar and degrees; the results' fields are SI.
"""

# %% An axle: the paper's truck, or an axle file (Axle.from_file("mytruck.toml")), with entries changed in the
# units of 'shimmy params' (degrees, bar, otherwise SI).
from comparisons.api import (
    Axle,
    TyrePressures,
    cycle_branches,
    hopf_points,
    shimmy_windows,
    simulate,
    stability_margins,
)

axle = Axle.paper().with_values(gamma=4.0)          # caster 4 degrees instead of the paper's 2.29
print(axle)

# %% Two tyre pressures (bar): the right tyre (wheel 1, theta1) at 1.5 bar, the left at 1.3 bar.
pressures = TyrePressures.of_bar(1.5, 1.3)
reduced = axle.reduced(effects="hcl,pt")
mbs = axle.mbs(fidelity="reduced", effects="hcl,pt")     # every assumption of the reduced model on

# %% Hopf points of both models: where straight running loses stability (shimmy onset).
reduced_hopf = hopf_points(reduced.family(pressures), vmax_kmh=400)
mbs_hopf = hopf_points(mbs.family(pressures), vmax_kmh=400)
print(reduced_hopf)
print(mbs_hopf)

# %% The limit-cycle branch born at the first Hopf point: how large the shimmy grows with speed.
first = reduced_hopf.points[0].speed_kmh
cycles = cycle_branches(reduced.family(pressures), vmin_kmh=max(0.5, first - 5), vmax_kmh=first + 30)
print(cycles)

# %% A simulation of each model, the same call for both: a speed ramp through the first Hopf point.
ramp = (max(0.5, first - 5), first + 15, 2.0)
runs = {name: simulate(model, pressures, ramp_kmh=ramp, duration_s=2.5, initial_deg={"theta1": 0.5})
        for name, model in (("reduced", reduced), ("mbs", mbs))}
for run in runs.values():
    print(run)

# %% The multibody model at full fidelity (every assumption off): how far the full geometry moves the onsets.
full_hopf = hopf_points(axle.mbs(fidelity="full", effects="hcl,pt").family(pressures), vmax_kmh=400)
print(full_hopf)

# %% Shimmy windows by mode: each Hopf point is named yaw or tramp by its critical eigenvector and paired with the
# next one of the same mode, so that a window runs from the speed where the mode becomes unstable (onset) to the
# speed where it becomes stable again (end).  Pairing the two models' Hopf points by index would compare an onset
# with an end; no Hopf point is left out.
windows = {"the reduced model": shimmy_windows(reduced.family(pressures), reduced_hopf),
           "the full geometry": shimmy_windows(axle.mbs(fidelity="full", effects="hcl,pt").family(pressures),
                                               full_hopf)}
for name, found in windows.items():
    print(found)
for mode in ("yaw", "tramp"):
    for name, found in windows.items():
        texts = [w.text() for w in found.windows if w.mode == mode] or [f"no {mode} window"]
        print(f"{name}: {'; '.join(texts)}")

# %% Stability margins: the least damping ratio of straight running over speed and pressure (both tyres alike),
# negative where a mode grows; the minimum over the grid with the speed and pressure where it occurs.
for model in (reduced, axle.mbs(fidelity="full", effects="hcl,pt")):
    margins = stability_margins(model, pressure_range_bar=(1.0, 3.0), vmax_kmh=200, pressure_points=5,
                                speed_points=41)
    print(margins)
