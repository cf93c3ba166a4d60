#!/usr/bin/env python3
"""Mapping quality against the slot-ID error rate, with and without Max-Mixture.

The paper's Fig. 7 experiment (section IV-A, offline mapping), extended: for every total ID
error rate R (split into digit confusions and unread digits) and every seed,
simulate a drive on the built-in lot, build the map in batch mode once with the
Max-Mixture back-end and once with plain Gaussians, and measure the map
(`parkslam eval-map`) and the trajectory (`parkslam eval-traj`) against the
ground truth.

Work folder (--work, a temporary folder by default, removed after a
successful run):
    WORK/r{R}/data/                       the simulated dataset
    WORK/r{R}/{robust}/map.json           the map
    WORK/r{R}/{robust}/trajectory.tum     the optimised trajectory
  with several seeds one level more: WORK/r{R}/seed{S}/data/, ...
  R is written with two decimals (r0.00, r0.05, ...).

Output folder (--out, docs/results/mapping by default):
    mapping_vs_id_errors.csv     one row per rate, seed and robust mode
                                 (with several seeds also rows with seed "mean")
    mapping_vs_id_errors.md      the table (means over the seeds)
    mapping_vs_id_errors.svg     corner RMSE and ID accuracy against the rate
    fig7_none.svg, fig7_maxmix.svg, fig7.md
                                 both maps at one rate (--fig-rate), first seed

Python 3 standard library only. Run from the repository root:
    scripts/mapping_experiment.py                     # the full experiment
    scripts/mapping_experiment.py --dry-run           # print the commands only
"""

from __future__ import annotations

import argparse
import concurrent.futures
import csv
import dataclasses
import io
import json
import math
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from typing import Callable, Sequence

DEFAULT_RATES = (0.0, 0.05, 0.10, 0.20, 0.30, 0.40)
ROBUST_MODES = ("maxmix", "none")
# Keys read from `parkslam eval-map --json`.
MAP_KEYS = (
    "slot_corner_rmse_m",
    "slots_true",
    "slots_matched",
    "slots_missed",
    "slots_spurious",
    "slots_duplicate",
    "id_accuracy",
    "temporary_id_share",
)
# Keys read from `parkslam eval-traj --json`.
TRAJ_KEYS = ("ate_rmse_m",)

CSV_COLUMNS = (
    ("rate", "id_error_rate"),
    ("confusion_rate", "id_confusion_rate"),
    ("partial_rate", "id_partial_rate"),
    ("seed", "seed"),
    ("robust", "robust"),
) + tuple((k, k) for k in MAP_KEYS + TRAJ_KEYS) + (("map_time_s", "map_time_s"),)

ROBUST_COLORS = {"maxmix": "#1f5fbf", "none": "#d62728"}
ROBUST_LABELS = {"maxmix": "Max-Mixture", "none": "no robust kernel"}


class ExperimentError(Exception):
    """A failure to report to the user (no traceback)."""


# ---------------------------------------------------------------- planning


@dataclass(frozen=True)
class Config:
    parkslam: str
    world: str
    rates: tuple[float, ...]
    confusion_share: float
    seeds: tuple[int, ...]
    robust_modes: tuple[str, ...]
    mode: str
    work: str
    out: str
    fig_rate: float
    jobs: int


@dataclass
class Unit:
    """One simulated dataset (a rate and a seed) and its maps."""

    rate: float
    seed: int
    folder: str

    @property
    def data(self) -> str:
        return os.path.join(self.folder, "data")

    def map_json(self, robust: str) -> str:
        return os.path.join(self.folder, robust, "map.json")

    def trajectory(self, robust: str) -> str:
        return os.path.join(self.folder, robust, "trajectory.tum")


def rate_label(rate: float) -> str:
    return f"r{rate:.2f}"


def format_rate(rate: float) -> str:
    """A rate for the command line, without float noise (0.6 * 0.2 -> 0.12)."""
    return f"{rate:.6g}"


def split_rate(rate: float, confusion_share: float) -> tuple[float, float]:
    confusion = round(rate * confusion_share, 9)
    return confusion, round(rate - confusion, 9)


def plan_units(config: Config) -> list[Unit]:
    units = []
    for rate in config.rates:
        for seed in config.seeds:
            folder = os.path.join(config.work, rate_label(rate))
            if len(config.seeds) > 1:
                folder = os.path.join(folder, f"seed{seed}")
            units.append(Unit(rate, seed, folder))
    return units


def simulate_command(config: Config, unit: Unit) -> list[str]:
    confusion, partial = split_rate(unit.rate, config.confusion_share)
    return [config.parkslam, "simulate", "--world", config.world, "--seed", str(unit.seed),
            "--out", unit.data, "--id-confusion-rate", format_rate(confusion),
            "--id-partial-rate", format_rate(partial)]


def map_command(config: Config, unit: Unit, robust: str) -> list[str]:
    return [config.parkslam, "map", unit.data, "--out", unit.map_json(robust),
            "--trajectory-out", unit.trajectory(robust), "--robust", robust,
            "--mode", config.mode]


def eval_map_command(config: Config, unit: Unit, robust: str) -> list[str]:
    return [config.parkslam, "eval-map", "--map", unit.map_json(robust), "--truth",
            os.path.join(unit.data, "groundtruth", "map.json"), "--json"]


def eval_traj_command(config: Config, unit: Unit, robust: str) -> list[str]:
    return [config.parkslam, "eval-traj", "--truth",
            os.path.join(unit.data, "groundtruth", "trajectory.tum"), "--estimate",
            unit.trajectory(robust), "--json"]


def render_command(config: Config, unit: Unit, robust: str, svg: str) -> list[str]:
    # A title of our own keeps the work folder's path out of the picture.
    letter = "b" if robust == "maxmix" else "a"
    title = (f"({letter}) {ROBUST_LABELS.get(robust, robust)}, "
             f"{100 * unit.rate:.0f} % ID errors, seed {unit.seed}")
    return [config.parkslam, "render", unit.map_json(robust), "--out", svg, "--trajectory",
            unit.trajectory(robust), "--title", title]


# ---------------------------------------------------------------- running


def run_command(command: Sequence[str]) -> str:
    """Runs a command; returns its stdout; raises ExperimentError on failure."""
    try:
        result = subprocess.run(list(command), capture_output=True, text=True, check=False)
    except OSError as error:
        raise ExperimentError(f"cannot run: {shlex.join(command)}\n{error}") from error
    if result.returncode != 0:
        stderr = result.stderr.strip() or result.stdout.strip() or "(no output)"
        raise ExperimentError(
            f"command failed with exit code {result.returncode}:\n  {shlex.join(command)}\n"
            f"{stderr}")
    return result.stdout


def parse_json_output(command: Sequence[str], stdout: str, keys: Sequence[str]) -> dict:
    text = stdout.strip()
    try:
        value = json.loads(text)
    except json.JSONDecodeError:
        # Tolerate a log line before the JSON object: take the last line.
        try:
            value = json.loads(text.splitlines()[-1]) if text else None
        except json.JSONDecodeError:
            value = None
    if not isinstance(value, dict):
        raise ExperimentError(f"expected one JSON object from:\n  {shlex.join(command)}\n"
                              f"got: {text[:500]!r}")
    missing = [k for k in keys if k not in value]
    if missing:
        raise ExperimentError(f"JSON from:\n  {shlex.join(command)}\nlacks {', '.join(missing)}")
    return {k: float(value[k]) for k in keys}


def run_unit(config: Config, unit: Unit,
             run: Callable[[Sequence[str]], str] = run_command) -> list[dict]:
    """Simulates, maps and evaluates one rate and seed; one row per robust mode."""
    os.makedirs(unit.folder, exist_ok=True)
    run(simulate_command(config, unit))
    confusion, partial = split_rate(unit.rate, config.confusion_share)
    rows = []
    for robust in config.robust_modes:
        os.makedirs(os.path.dirname(unit.map_json(robust)), exist_ok=True)
        start = time.perf_counter()
        run(map_command(config, unit, robust))
        map_time_s = time.perf_counter() - start
        command = eval_map_command(config, unit, robust)
        row = {"rate": unit.rate, "confusion_rate": confusion, "partial_rate": partial,
               "seed": unit.seed, "robust": robust}
        row.update(parse_json_output(command, run(command), MAP_KEYS))
        command = eval_traj_command(config, unit, robust)
        row.update(parse_json_output(command, run(command), TRAJ_KEYS))
        row["map_time_s"] = map_time_s
        rows.append(row)
    return rows


def run_all(config: Config, units: Sequence[Unit]) -> list[dict]:
    rows: list[dict] = []
    if config.jobs <= 1:
        for unit in units:
            print(f"  rate {unit.rate:.2f}, seed {unit.seed}", file=sys.stderr, flush=True)
            rows.extend(run_unit(config, unit))
    else:
        with concurrent.futures.ThreadPoolExecutor(max_workers=config.jobs) as pool:
            futures = [pool.submit(run_unit, config, unit) for unit in units]
            try:
                for future in futures:
                    rows.extend(future.result())
            except BaseException:
                for pending in futures:
                    pending.cancel()
                raise
    rows.sort(key=lambda r: (r["rate"], r["seed"], config.robust_modes.index(r["robust"])))
    return rows


# ---------------------------------------------------------------- summarising


def mean_rows(rows: Sequence[dict], robust_modes: Sequence[str]) -> list[dict]:
    """One row per rate and robust mode: the mean over the seeds (seed 'mean')."""
    groups: dict[tuple[float, str], list[dict]] = {}
    for row in rows:
        groups.setdefault((row["rate"], row["robust"]), []).append(row)
    means = []
    for (rate, robust), group in sorted(groups.items(),
                                        key=lambda g: (g[0][0], robust_modes.index(g[0][1]))):
        mean = {"rate": rate, "confusion_rate": group[0]["confusion_rate"],
                "partial_rate": group[0]["partial_rate"], "seed": "mean", "robust": robust}
        for key in MAP_KEYS + TRAJ_KEYS + ("map_time_s",):
            mean[key] = sum(float(r[key]) for r in group) / len(group)
        mean["seeds"] = len(group)
        means.append(mean)
    return means


def format_csv_value(value) -> str:
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        return f"{value:.6g}"
    return str(value)


def write_atomic(path: str, text: str) -> None:
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    handle, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp_", suffix=os.path.basename(path))
    try:
        with os.fdopen(handle, "w", encoding="utf-8", newline="") as f:
            f.write(text)
        # mkstemp creates the file private; give it the usual permissions.
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def csv_text(rows: Sequence[dict]) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow([header for _, header in CSV_COLUMNS])
    for row in rows:
        writer.writerow([format_csv_value(row[key]) for key, _ in CSV_COLUMNS])
    return buffer.getvalue()


def _count(value: float) -> str:
    """An integer count, or a mean over seeds with one decimal."""
    return str(int(value)) if float(value).is_integer() else f"{value:.1f}"


def markdown_table(rows: Sequence[dict]) -> str:
    lines = [
        "| ID error rate | robust | corner RMSE (m) | matched / true | missed | spurious "
        "| duplicates | ID accuracy | temporary IDs | trajectory ATE (m) | map time (s) |",
        "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(
            f"| {100 * r['rate']:.0f} % | {r['robust']} | {r['slot_corner_rmse_m']:.3f} "
            f"| {_count(r['slots_matched'])} / {_count(r['slots_true'])} "
            f"| {_count(r['slots_missed'])} | {_count(r['slots_spurious'])} "
            f"| {_count(r['slots_duplicate'])} | {100 * r['id_accuracy']:.1f} % "
            f"| {100 * r['temporary_id_share']:.1f} % | {r['ate_rmse_m']:.3f} "
            f"| {r['map_time_s']:.2f} |")
    return "\n".join(lines) + "\n"


def markdown_report(config: Config, table_rows: Sequence[dict]) -> str:
    seeds = config.seeds
    seed_text = (f"seed {seeds[0]}" if len(seeds) == 1
                 else f"mean over {len(seeds)} seeds ({seeds[0]}..{seeds[-1]}; per-seed rows "
                      "in the CSV)")
    return (
        "# Mapping against slot-ID errors\n\n"
        "The paper's Fig. 7 experiment, extended (`scripts/mapping_experiment.py`): the "
        f"`{config.world}` lot, {seed_text}. The ID error rate is the share of slot-ID "
        f"readings that are wrong: {100 * config.confusion_share:.0f} % of it one digit "
        f"confused, {100 * (1 - config.confusion_share):.0f} % one digit unread. Maps built "
        f"with `parkslam map --mode {config.mode}`, measured with `parkslam eval-map` (after an "
        "SE(2) alignment onto the truth; slots match within 1 m of entrance midpoint) and "
        "`parkslam eval-traj`. ID accuracy counts a temporary ID as right where the painted "
        "ID is missing or illegible. Map time is wall-clock time of `parkslam map`"
        + (f" with {config.jobs} runs in parallel" if config.jobs > 1 else "") + ".\n\n"
        "![corner RMSE and ID accuracy against the ID error rate](mapping_vs_id_errors.svg)\n\n"
        + markdown_table(table_rows))


# ---------------------------------------------------------------- SVG plot


def nice_ticks(lo: float, hi: float, target: int = 5) -> list[float]:
    """Round tick values covering [lo, hi] (steps of 1, 2 or 5 times 10^k)."""
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ValueError("nice_ticks: bounds must be finite")
    if hi < lo:
        lo, hi = hi, lo
    if hi - lo < 1e-12:
        hi = lo + (abs(lo) if lo != 0 else 1.0)
    raw = (hi - lo) / max(target, 1)
    magnitude = 10.0 ** math.floor(math.log10(raw))
    step = next(m * magnitude for m in (1.0, 2.0, 5.0, 10.0) if m * magnitude >= raw - 1e-12)
    first = math.floor(lo / step + 1e-9) * step
    ticks = []
    k = 0
    while True:
        value = first + k * step
        ticks.append(round(value, 12))
        if value >= hi - 1e-9 * step:
            break
        k += 1
    return ticks


def _fmt_tick(value: float, step: float) -> str:
    decimals = max(0, -math.floor(math.log10(step) + 1e-9)) if step > 0 else 0
    return f"{value:.{decimals}f}"


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


@dataclass
class Panel:
    title: str
    y_label: str
    series: dict[str, list[tuple[float, float]]] = field(default_factory=dict)
    include_zero: bool = False  # the y axis reaches down (or up) to 0
    y_max: float | None = None  # a fixed upper end (None: from the data)


def _panel_svg(panel: Panel, x0: float, y0: float, width: float, height: float,
               x_ticks: Sequence[float], x_label: str) -> list[str]:
    left, right, top, bottom = 62.0, 14.0, 30.0, 46.0
    px0, px1 = x0 + left, x0 + width - right
    py0, py1 = y0 + top, y0 + height - bottom  # py1 is the x axis
    values = [y for points in panel.series.values() for _, y in points if math.isfinite(y)]
    lo, hi = (min(values), max(values)) if values else (0.0, 1.0)
    if panel.include_zero:
        lo, hi = min(lo, 0.0), max(hi, 0.0)
    if panel.y_max is not None:
        hi = panel.y_max
        lo = min(lo, hi)
    if hi - lo < 1e-9:  # a flat line: open the axis away from the fixed end
        span = max(0.1 * abs(hi), 1e-3)
        lo, hi = (lo - span, hi) if panel.y_max is not None else (lo, hi + span)
    y_ticks = nice_ticks(lo, hi)
    y_lo, y_hi = y_ticks[0], y_ticks[-1]
    x_lo, x_hi = x_ticks[0], x_ticks[-1]

    def sx(x: float) -> float:
        return px0 + (x - x_lo) / (x_hi - x_lo) * (px1 - px0)

    def sy(y: float) -> float:
        return py1 - (y - y_lo) / (y_hi - y_lo) * (py1 - py0)

    out = ['<g class="panel">',
           f'<text x="{(px0 + px1) / 2:.1f}" y="{y0 + 18:.1f}" text-anchor="middle" '
           f'font-size="14" font-weight="bold">{_escape(panel.title)}</text>']
    y_step = y_ticks[1] - y_ticks[0] if len(y_ticks) > 1 else 1.0
    for y in y_ticks:
        out.append(f'<line x1="{px0:.1f}" y1="{sy(y):.1f}" x2="{px1:.1f}" y2="{sy(y):.1f}" '
                   'stroke="#e4e4e4" stroke-width="1"/>')
        out.append(f'<line x1="{px0 - 5:.1f}" y1="{sy(y):.1f}" x2="{px0:.1f}" y2="{sy(y):.1f}" '
                   'stroke="black" stroke-width="1"/>')
        out.append(f'<text x="{px0 - 8:.1f}" y="{sy(y) + 4:.1f}" text-anchor="end" '
                   f'font-size="11">{_fmt_tick(y, y_step)}</text>')
    x_step = x_ticks[1] - x_ticks[0] if len(x_ticks) > 1 else 1.0
    for x in x_ticks:
        out.append(f'<line x1="{sx(x):.1f}" y1="{py1:.1f}" x2="{sx(x):.1f}" y2="{py1 + 5:.1f}" '
                   'stroke="black" stroke-width="1"/>')
        out.append(f'<text x="{sx(x):.1f}" y="{py1 + 18:.1f}" text-anchor="middle" '
                   f'font-size="11">{_fmt_tick(x, x_step)}</text>')
    out.append(f'<rect x="{px0:.1f}" y="{py0:.1f}" width="{px1 - px0:.1f}" '
               f'height="{py1 - py0:.1f}" fill="none" stroke="black" stroke-width="1"/>')
    out.append(f'<text x="{(px0 + px1) / 2:.1f}" y="{py1 + 38:.1f}" text-anchor="middle" '
               f'font-size="12">{_escape(x_label)}</text>')
    cy = (py0 + py1) / 2
    out.append(f'<text x="{x0 + 16:.1f}" y="{cy:.1f}" text-anchor="middle" font-size="12" '
               f'transform="rotate(-90 {x0 + 16:.1f} {cy:.1f})">{_escape(panel.y_label)}</text>')
    for name, points in panel.series.items():
        color = ROBUST_COLORS.get(name, "black")
        finite = [(x, y) for x, y in points if math.isfinite(y)]
        if len(finite) > 1:
            path = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in finite)
            out.append(f'<polyline class="series" data-name="{_escape(name)}" points="{path}" '
                       f'fill="none" stroke="{color}" stroke-width="2"/>')
        for x, y in finite:
            out.append(f'<circle cx="{sx(x):.1f}" cy="{sy(y):.1f}" r="3.5" fill="{color}"/>')
    out.append("</g>")
    return out


def plot_svg(rows: Sequence[dict], robust_modes: Sequence[str]) -> str:
    """Two panels: corner RMSE (m) and ID accuracy (%) against the ID error rate (%)."""
    rmse = Panel("Slot corner RMSE", "corner RMSE (m)", include_zero=True)
    accuracy = Panel("Slot-ID accuracy", "ID accuracy (%)", y_max=100.0)
    for robust in robust_modes:
        mine = sorted((r for r in rows if r["robust"] == robust), key=lambda r: r["rate"])
        rmse.series[robust] = [(100 * r["rate"], float(r["slot_corner_rmse_m"])) for r in mine]
        accuracy.series[robust] = [(100 * r["rate"], 100 * float(r["id_accuracy"]))
                                   for r in mine]
    rates = [100 * r["rate"] for r in rows] or [0.0, 1.0]
    x_ticks = nice_ticks(min(0.0, min(rates)), max(rates), 4)

    panel_w, panel_h, legend_h = 380.0, 300.0, 34.0
    width, height = 2 * panel_w, panel_h + legend_h
    x_label = "ID error rate (%)"
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
           f'viewBox="0 0 {width:.0f} {height:.0f}" font-family="sans-serif">',
           f'<rect width="{width:.0f}" height="{height:.0f}" fill="white"/>']
    out += _panel_svg(rmse, 0.0, 0.0, panel_w, panel_h, x_ticks, x_label)
    out += _panel_svg(accuracy, panel_w, 0.0, panel_w, panel_h, x_ticks, x_label)
    out.append('<g class="legend">')
    x = width / 2 - 110.0 * len(robust_modes) / 2
    y = panel_h + legend_h / 2
    for robust in robust_modes:
        color = ROBUST_COLORS.get(robust, "black")
        out.append(f'<line x1="{x:.1f}" y1="{y:.1f}" x2="{x + 24:.1f}" y2="{y:.1f}" '
                   f'stroke="{color}" stroke-width="2"/>')
        out.append(f'<circle cx="{x + 12:.1f}" cy="{y:.1f}" r="3.5" fill="{color}"/>')
        out.append(f'<text x="{x + 30:.1f}" y="{y + 4:.1f}" font-size="12">'
                   f'{_escape(ROBUST_LABELS.get(robust, robust))}</text>')
        x += 150.0
    out.append("</g>")
    out.append("</svg>")
    return "\n".join(out) + "\n"


# ---------------------------------------------------------------- Fig. 7


def fig7_markdown(rows_at_rate: Sequence[dict], rate: float, seed: int) -> str:
    by_mode = {r["robust"]: r for r in rows_at_rate}
    modes = [m for m in ("none", "maxmix") if m in by_mode]
    header = "| | " + " | ".join(ROBUST_LABELS.get(m, m) for m in modes) + " |"
    lines = [
        "# Fig. 7: the map with and without the robust back-end\n",
        f"ID error rate {100 * rate:.0f} %, seed {seed}: (a) the map optimised with plain "
        "Gaussians, (b) with Max-Mixture. Made by `scripts/mapping_experiment.py`.\n",
        header,
        "|---|" + "---|" * len(modes),
        "| map | " + " | ".join(f"![{m}](fig7_{m}.svg)" for m in modes) + " |",
    ]
    metrics = (
        ("corner RMSE", lambda r: f"{r['slot_corner_rmse_m']:.3f} m"),
        ("matched / true", lambda r: f"{_count(r['slots_matched'])} / {_count(r['slots_true'])}"),
        ("missed / spurious / duplicates", lambda r: f"{_count(r['slots_missed'])} / "
         f"{_count(r['slots_spurious'])} / {_count(r['slots_duplicate'])}"),
        ("ID accuracy", lambda r: f"{100 * r['id_accuracy']:.1f} %"),
        ("temporary IDs", lambda r: f"{100 * r['temporary_id_share']:.1f} %"),
        ("trajectory ATE", lambda r: f"{r['ate_rmse_m']:.3f} m"),
    )
    for label, text in metrics:
        lines.append(f"| {label} | " + " | ".join(text(by_mode[m]) for m in modes) + " |")
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------- main


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        description="Map quality against the slot-ID error rate, with and without the "
                    "Max-Mixture back-end (the paper's Fig. 7 experiment, extended). Drives "
                    "the parkslam CLI: simulate, map, eval-map, eval-traj, render.",
        epilog="Outputs: mapping_vs_id_errors.{csv,md,svg}, fig7_none.svg, fig7_maxmix.svg, "
               "fig7.md in --out.")
    parser.add_argument("--parkslam", default=os.path.join("build", "bin", "parkslam"),
                        help="the parkslam binary (default: %(default)s)")
    parser.add_argument("--out", default=os.path.join("docs", "results", "mapping"),
                        help="output folder (default: %(default)s)")
    parser.add_argument("--work", default=None,
                        help="work folder for datasets and maps, kept afterwards "
                             "(default: a temporary folder, removed after a successful run)")
    parser.add_argument("--seeds", type=int, default=1,
                        help="number of seeds, from --first-seed on (default: %(default)s); "
                             "with several, tables and plot show the mean")
    parser.add_argument("--first-seed", type=int, default=1, help="(default: %(default)s)")
    parser.add_argument("--rates", default=",".join(f"{r:g}" for r in DEFAULT_RATES),
                        help="total ID error rates, comma-separated (default: %(default)s)")
    parser.add_argument("--confusion-share", type=float, default=0.6,
                        help="share of the error rate that is digit confusion; the rest is "
                             "unread digits (default: %(default)s)")
    parser.add_argument("--fig-rate", type=float, default=0.20,
                        help="the rate whose maps are drawn side by side (default: %(default)s)")
    parser.add_argument("--world", default="default",
                        help="built-in world or scenario YAML (default: %(default)s)")
    parser.add_argument("--mode", default="batch", help="mapper mode (default: %(default)s)")
    parser.add_argument("--jobs", type=int, default=1,
                        help="datasets processed in parallel (default: %(default)s; map times "
                             "are only comparable with 1)")
    parser.add_argument("--dry-run", action="store_true",
                        help="print the commands instead of running them")
    return parser.parse_args(argv)


def make_config(args: argparse.Namespace, work: str) -> Config:
    try:
        rates = tuple(float(r) for r in args.rates.split(",") if r.strip())
    except ValueError as error:
        raise ExperimentError(f"--rates: {error}") from error
    if not rates or any(not 0.0 <= r <= 1.0 for r in rates):
        raise ExperimentError("--rates: expected numbers in [0, 1]")
    if len({rate_label(r) for r in rates}) != len(rates):
        raise ExperimentError("--rates: two rates share a folder name (two decimals)")
    if not 0.0 <= args.confusion_share <= 1.0:
        raise ExperimentError("--confusion-share: expected a number in [0, 1]")
    if args.seeds < 1:
        raise ExperimentError("--seeds: expected at least 1")
    if args.jobs < 1:
        raise ExperimentError("--jobs: expected at least 1")
    if not any(abs(r - args.fig_rate) < 1e-9 for r in rates):
        raise ExperimentError(f"--fig-rate {args.fig_rate:g} is not one of --rates {args.rates}")
    return Config(parkslam=args.parkslam, world=args.world, rates=rates,
                  confusion_share=args.confusion_share,
                  seeds=tuple(range(args.first_seed, args.first_seed + args.seeds)),
                  robust_modes=ROBUST_MODES, mode=args.mode, work=work, out=args.out,
                  fig_rate=args.fig_rate, jobs=args.jobs)


def fig7_unit(config: Config, units: Sequence[Unit]) -> Unit:
    return next(u for u in units
                if abs(u.rate - config.fig_rate) < 1e-9 and u.seed == config.seeds[0])


def dry_run(config: Config) -> None:
    units = plan_units(config)
    for unit in units:
        print(shlex.join(simulate_command(config, unit)))
        for robust in config.robust_modes:
            print(shlex.join(map_command(config, unit, robust)))
            print(shlex.join(eval_map_command(config, unit, robust)))
            print(shlex.join(eval_traj_command(config, unit, robust)))
    unit = fig7_unit(config, units)
    for robust in config.robust_modes:
        print(shlex.join(render_command(config, unit, robust,
                                        os.path.join(config.out, f"fig7_{robust}.svg"))))


def check_binary(path: str) -> None:
    if os.path.isfile(path) and os.access(path, os.X_OK):
        return
    if os.sep not in path and shutil.which(path):
        return
    raise ExperimentError(f"parkslam binary not found or not executable: {path}\n"
                          "build it (scripts/build.sh) or pass --parkslam PATH")


def run_experiment(config: Config) -> list[dict]:
    check_binary(config.parkslam)
    units = plan_units(config)
    print(f"mapping experiment: {len(config.rates)} rates x {len(config.seeds)} seeds x "
          f"{len(config.robust_modes)} back-ends in {config.work}", file=sys.stderr)
    rows = run_all(config, units)

    table_rows = mean_rows(rows, config.robust_modes) if len(config.seeds) > 1 else rows
    csv_rows = list(rows) + (table_rows if len(config.seeds) > 1 else [])
    out = config.out
    os.makedirs(out, exist_ok=True)
    write_atomic(os.path.join(out, "mapping_vs_id_errors.csv"), csv_text(csv_rows))
    write_atomic(os.path.join(out, "mapping_vs_id_errors.md"), markdown_report(config, table_rows))
    write_atomic(os.path.join(out, "mapping_vs_id_errors.svg"),
                 plot_svg(table_rows, config.robust_modes))

    unit = fig7_unit(config, units)
    for robust in config.robust_modes:
        run_command(render_command(config, unit, robust, os.path.join(out, f"fig7_{robust}.svg")))
    at_rate = [r for r in rows if r["rate"] == unit.rate and r["seed"] == unit.seed]
    write_atomic(os.path.join(out, "fig7.md"), fig7_markdown(at_rate, unit.rate, unit.seed))
    print(f"written to {out}: mapping_vs_id_errors.{{csv,md,svg}}, fig7_none.svg, "
          "fig7_maxmix.svg, fig7.md", file=sys.stderr)
    return rows


def main(argv: Sequence[str] | None = None) -> int:
    args = parse_args(argv)
    temporary_work = args.work is None and not args.dry_run
    work = None
    try:
        # A dry run without --work shows the placeholder WORK.
        config = make_config(args, args.work or "WORK")
        if args.dry_run:
            dry_run(config)
            return 0
        check_binary(config.parkslam)
        if temporary_work:
            work = tempfile.mkdtemp(prefix="parkslam_mapping_")
            config = dataclasses.replace(config, work=work)
        run_experiment(config)
    except ExperimentError as error:
        print(f"mapping_experiment: error: {error}", file=sys.stderr)
        if work is not None:
            print(f"mapping_experiment: work folder kept for inspection: {work}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("mapping_experiment: interrupted", file=sys.stderr)
        return 130
    if work is not None:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
