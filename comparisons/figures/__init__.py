"""The paper's figures recomputed by this project: a registry figure number -> drawing function.

Each drawing function takes a :class:`DiagramStore` (which computes and remembers Hopf and cycle diagrams, so
that two figures sharing a diagram compute it once) and returns a :class:`Drawing`: the matplotlib figure plus
notes (the computed numbers worth comparing with the paper's text).  Axes and units follow the paper: speed in
km/h, pressure in bar, lengths in m, stiffness in N/m, slip angles in degrees.

Modules by kind of figure: :mod:`.tyre_figures` (2, 12, 16), :mod:`.hopf_figures` (5-7, 13, 14),
:mod:`.cumulative` (17), :mod:`.cycle_figures` (3, 4, 9, 15), :mod:`.simulation_figures` (10, 11),
:mod:`.cycle_curve_figures` (8 and 18: Hopf curves with cycle-fold and torus curves); :mod:`.beside_figures` draws
figures 3-5, 8, 9 and 17 for the MBS beside the reduced model (``shimmy figures --model mbs``; the registry
:data:`BESIDE`); :mod:`.registry` makes them, :mod:`.drawing` holds the shared drawing helpers.

Figures that need what the project cannot compute yet are listed in :data:`UNAVAILABLE` with the reason;
asking for one raises :class:`FigureUnavailable`.  Making such a figure available means registering a drawing
function with :func:`register` (and removing its entry from :data:`UNAVAILABLE`).
"""

from axles import paper_reference as paper  # noqa: F401  (figures.paper: the printed values the notes cite)
from comparisons.figures import (  # noqa: F401
    beside_figures,
    cumulative,
    cycle_curve_figures,
    cycle_figures,
    hopf_figures,
    simulation_figures,
    tyre_figures,
)
from comparisons.figures.cumulative import P17_BAR, Z1, Z2, ZOOM_SEEDS, uncovered  # noqa: F401
from comparisons.figures.cycle_figures import hopf_names  # noqa: F401
from comparisons.figures.hopf_figures import pressure_key  # noqa: F401
from comparisons.figures.registry import (  # noqa: F401
    BESIDE,
    PAPER_TITLES,
    REGISTRY,
    UNAVAILABLE,
    CycleKey,
    DiagramKey,
    DiagramStore,
    Drawing,
    FigureEntry,
    FigureResult,
    FigureUnavailable,
    available_figures,
    make_figure,
    make_figures,
    register,
    store_cycles,
    unavailable_reason,
)
