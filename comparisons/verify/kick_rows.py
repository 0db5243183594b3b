"""The kick threshold (:mod:`comparisons.studies.kick`) as a row of ``shimmy verify``: the smallest initial theta1 that
leaves the lower of two coexisting stable states, and the two runs that bracket it."""

from __future__ import annotations

import math

from comparisons.verify.report import CheckStatus


def kick_verdict(kick, model: str) -> tuple[dict, CheckStatus, str]:
    """(cells, status, text) of one threshold found in ``model`` (a label for the report): passed when two runs,
    just below and just above it, end on the two states; information when no kick up to the limit leaves the
    lower state; could not check when a run did not settle (the bracket is not trustworthy: no model disagrees
    with another, and no computation failed)."""
    from comparisons.studies.kick import KickStatus
    found = kick.status is KickStatus.FOUND
    cells = {"kick_deg": math.degrees(kick.kick) if found else None}
    if found:
        text = (f"{model}: an initial theta1 of {math.degrees(kick.stays):.3f} deg stays on {kick.lower.label}, "
                f"{math.degrees(kick.leaves):.3f} deg leaves for {kick.upper.label} ({kick.runs} runs; the unstable "
                f"cycle between them has max |theta1| {math.degrees(kick.unstable_theta1):.2f} deg)")
        return cells, CheckStatus.PASS, text
    status = CheckStatus.INFO if kick.status is KickStatus.NOT_LEFT else CheckStatus.COULD_NOT_CHECK
    return cells, status, f"{model}: kick not bracketed: {kick.status.value}"
