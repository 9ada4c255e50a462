"""What the study plots share: the error axis' label (the metric and its unit), and how they
mark the levels (converge) and runs (work-precision) that no fit and no cheapest-method table
counts: one marker per reason, drawn over the curve's own marker, and one legend entry per
reason present, so that a saturated level, an unstable one and one the reference cannot certify
are told apart at a glance (their statuses: studies/convergence.hpp, studies/work_precision.hpp).
"""
import textwrap


def error_label(metric, unit, terms):
    """The error axis' label: the metric and its unit, and on a second line what it is taken
    from ("relative error [1]" over "largest of book.rotation / pi rad, book.corner / 2 m")."""
    label = f"{metric} error [{unit}]"
    if terms:
        label += "\n" + textwrap.shorten(terms.replace("pi rad", "π rad"), width=70,
                                          placeholder=" …")
    return label


# status -> (legend text, marker style). Shapes differ as well as colours, so that the marks
# survive a grey-scale print.
STYLES = {
    "saturated": ("saturated: error ≥ 1/3 of its range",
                  dict(marker="x", color="k", markersize=9, markeredgewidth=1.6)),
    "unstable": ("unstable: broke an invariant",
                 dict(marker="^", markerfacecolor="none", markeredgecolor="tab:red",
                      markersize=12, markeredgewidth=1.6)),
    "uncertified": ("uncertified: < 100× the reference's error",
                    dict(marker="o", markerfacecolor="none", markeredgecolor="k", markersize=13,
                         markeredgewidth=1.4)),
}
# Every other status but "ok" (above step limit, not decreasing, round-off, off-joints): one
# entry that names the ones present.
OTHER = dict(marker="+", color="dimgray", markersize=11, markeredgewidth=1.6)


def category(status):
    """The key of STYLES a status is drawn with, "other" for the rest, None for "ok" and failed
    runs (no error to draw)."""
    if status == "ok" or status.startswith("failed"):
        return None
    return status if status in STYLES else "other"


def mark(ax, points):
    """Draws (x, y, status) points that are not "ok" with their reason's marker and adds one
    legend entry per reason present (a proxy artist, so that each reason is listed once)."""
    present = {}
    for x, y, status in points:
        key = category(status)
        if key is None:
            continue
        style = STYLES[key][1] if key in STYLES else OTHER
        ax.plot([x], [y], linestyle="none", zorder=5, **style)
        present.setdefault(key, set()).add(status)
    return present


def legend_entries(ax, present):
    """The legend entries of the reasons in `present` (the union of mark's results), in a fixed
    order: saturated, unstable, uncertified, other."""
    for key in ("saturated", "unstable", "uncertified"):
        if key in present:
            text, style = STYLES[key]
            ax.plot([], [], linestyle="none", label=text, **style)
    if "other" in present:
        names = ", ".join(sorted(present["other"]))
        ax.plot([], [], linestyle="none", label=f"not counted: {names} (see status)", **OTHER)


def merge(total, present):
    """Adds mark's result `present` to `total` (both status sets by reason)."""
    for key, statuses in present.items():
        total.setdefault(key, set()).update(statuses)
    return total
