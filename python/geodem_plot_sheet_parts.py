"""The sheet's parts in a pull-out (run-out, bend, trench part), used by geodem_plot.py and
geodem_plot_pullout_series.py: what each part takes off the sheet and the grains' normal
force on it against the pull (the mean over the seeds when there are several), beside the
terms of the slippage estimate (dashed: F1, the capstan factor's share and F2 above; the
at-rest normal forces they assume below).
"""
import numpy as np

PARTS = (("runout", "run-out", "tab:blue"), ("bend", "bend", "tab:orange"),
         ("trench", "trench part", "tab:green"))


def mean_curves(histories, columns):
    """The columns averaged over the histories on a common displacement grid (m)."""
    top = min(h["displacement"][-1] for h in histories)
    grid = np.linspace(0.0, top, 200)
    return grid, {c: np.mean([np.interp(grid, h["displacement"], h[c]) for h in histories],
                             axis=0) for c in columns}


def plot_sheet_parts(plt, out, save, histories, estimate, made, name="sheet_parts.png"):
    """histories: dicts of numpy columns (history.csv of a pull-out); estimate: the
    summary's sheet_parts.slip_estimate, or None."""
    histories = [h for h in histories if "runout_carried" in h and h["displacement"].size > 1]
    if not histories:
        return
    columns = [p + "_" + q for p, _, _ in PARTS for q in ("carried", "normal")]
    grid, mean = mean_curves(histories, columns)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6.6, 6.8), sharex=True)
    for part, label, colour in PARTS:
        top.plot(grid * 1e3, mean[part + "_carried"] / 1e3, color=colour, label=label)
        bottom.plot(grid * 1e3, mean[part + "_normal"] / 1e3, color=colour, label=label)
        e = (estimate or {}).get(part, {})
        if "carried" in e:
            top.axhline(e["carried"] / 1e3, color=colour, ls="--", lw=0.9)
        if "normal" in e:
            bottom.axhline(e["normal"] / 1e3, color=colour, ls="--", lw=0.9)
    seeds = f" (mean of {len(histories)} seeds)" if len(histories) > 1 else ""
    top.set_title("Where the tension goes" + seeds + "; dashed: the slippage estimate",
                  fontsize=10)
    top.set_ylabel("tension taken off the sheet (kN/m)")
    bottom.set_ylabel("normal force of the grains (kN/m)")
    bottom.set_xlabel("pulled-end displacement (mm)")
    for ax in (top, bottom):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    save(fig, out, name, made)
