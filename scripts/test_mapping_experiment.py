"""Tests of scripts/mapping_experiment.py: the writers on made-up numbers and the
plumbing against a fake parkslam binary.

Run from the repository root:  python3 -m unittest discover -s scripts -p 'test_*.py'
"""

import contextlib
import csv
import io
import os
import sys
import tempfile
import textwrap
import unittest
import xml.etree.ElementTree as ElementTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mapping_experiment as experiment  # noqa: E402

SVG_NS = "{http://www.w3.org/2000/svg}"

# A stand-in for build/bin/parkslam: writes plausible files and JSON whose
# numbers depend on the error rate and the robust mode. FAKE_FAIL=<command>
# makes that command fail.
FAKE_PARKSLAM = textwrap.dedent("""\
    #!/usr/bin/env python3
    import json, os, sys
    args = sys.argv[1:]
    command = args[0]
    def option(name):
        return args[args.index(name) + 1]
    if os.environ.get("FAKE_FAIL") == command:
        print("boom: " + command + " went wrong", file=sys.stderr)
        sys.exit(3)
    if command == "simulate":
        out = option("--out")
        os.makedirs(os.path.join(out, "groundtruth"), exist_ok=True)
        rate = float(option("--id-confusion-rate")) + float(option("--id-partial-rate"))
        with open(os.path.join(out, "rate"), "w") as f:
            f.write(str(rate))
        for name in ("map.json", "trajectory.tum"):
            open(os.path.join(out, "groundtruth", name), "w").close()
    elif command == "map":
        with open(os.path.join(args[1], "rate")) as f:
            rate = float(f.read())
        with open(option("--out"), "w") as f:
            json.dump({"rate": rate, "robust": option("--robust")}, f)
        open(option("--trajectory-out"), "w").close()
    elif command == "eval-map":
        with open(option("--map")) as f:
            m = json.load(f)
        bad = m["rate"] * (0.2 if m["robust"] == "maxmix" else 1.0)
        print(json.dumps({"slot_corner_rmse_m": 0.05 + bad, "slots_true": 127,
                          "slots_matched": 120, "slots_missed": 7, "slots_spurious": 2,
                          "slots_duplicate": int(10 * bad), "id_accuracy": 1.0 - bad,
                          "temporary_id_share": 0.1, "tags_true": 60, "tags_matched": 60}))
    elif command == "eval-traj":
        print(json.dumps({"ate_rmse_m": 0.08, "matched_poses": 100}))
    elif command == "render":
        with open(option("--out"), "w") as f:
            f.write("<svg xmlns='http://www.w3.org/2000/svg'/>")
    else:
        sys.exit("unknown command " + command)
    """)


def made_up_rows(seeds=(1,)):
    rows = []
    for rate in experiment.DEFAULT_RATES:
        for seed in seeds:
            for robust in experiment.ROBUST_MODES:
                bad = rate * (0.2 if robust == "maxmix" else 1.0) + 0.01 * seed
                confusion, partial = experiment.split_rate(rate, 0.6)
                rows.append({"rate": rate, "confusion_rate": confusion, "partial_rate": partial,
                             "seed": seed, "robust": robust, "slot_corner_rmse_m": 0.04 + bad,
                             "slots_true": 127.0, "slots_matched": 125.0, "slots_missed": 2.0,
                             "slots_spurious": 1.0, "slots_duplicate": float(round(20 * bad)),
                             "id_accuracy": 0.98 - bad, "temporary_id_share": 0.05 + rate / 3,
                             "ate_rmse_m": 0.1 + bad, "map_time_s": 1.5})
    return rows


def run_main(argv):
    """Runs main(argv); returns (exit code, stdout, stderr)."""
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        code = experiment.main(argv)
    return code, stdout.getvalue(), stderr.getvalue()


class RatesTest(unittest.TestCase):
    def test_split_is_sixty_forty_by_default(self):
        self.assertEqual(experiment.split_rate(0.20, 0.6), (0.12, 0.08))
        self.assertEqual(experiment.split_rate(0.0, 0.6), (0.0, 0.0))

    def test_rates_are_written_without_float_noise(self):
        self.assertEqual(experiment.format_rate(0.6 * 0.3), "0.18")
        self.assertEqual(experiment.rate_label(0.05), "r0.05")
        self.assertEqual(experiment.rate_label(0.4), "r0.40")


class NiceTicksTest(unittest.TestCase):
    def test_ticks_cover_the_range_in_round_steps(self):
        self.assertEqual(experiment.nice_ticks(0.0, 0.37), [0.0, 0.1, 0.2, 0.3, 0.4])
        self.assertEqual(experiment.nice_ticks(0.0, 40.0, 4), [0.0, 10.0, 20.0, 30.0, 40.0])
        self.assertEqual(experiment.nice_ticks(93.2, 100.0), [92.0, 94.0, 96.0, 98.0, 100.0])

    def test_flat_range_still_gives_two_ticks(self):
        self.assertGreaterEqual(len(experiment.nice_ticks(5.0, 5.0)), 2)


class WritersTest(unittest.TestCase):
    def test_csv_has_one_row_per_rate_seed_and_mode(self):
        text = experiment.csv_text(made_up_rows())
        records = list(csv.DictReader(io.StringIO(text)))
        self.assertEqual(len(records), 12)
        self.assertEqual(records[0]["id_error_rate"], "0")
        self.assertEqual(records[0]["robust"], "maxmix")
        self.assertEqual(records[4]["id_confusion_rate"], "0.06")
        for key in experiment.MAP_KEYS + experiment.TRAJ_KEYS + ("map_time_s",):
            self.assertIn(key, records[0])

    def test_mean_rows_average_the_seeds(self):
        means = experiment.mean_rows(made_up_rows(seeds=(1, 2, 3)), experiment.ROBUST_MODES)
        self.assertEqual(len(means), 12)
        self.assertEqual(means[0]["seed"], "mean")
        self.assertAlmostEqual(means[0]["slot_corner_rmse_m"], 0.04 + 0.02)  # seeds 1..3
        self.assertEqual(means[0]["seeds"], 3)

    def test_markdown_table_shows_every_row_in_units(self):
        table = experiment.markdown_table(made_up_rows())
        lines = table.strip().splitlines()
        self.assertEqual(len(lines), 2 + 12)
        self.assertIn("| 20 % | none | 0.250 | 125 / 127 | 2 | 1 | 4 | 77.0 % |", table)

    def test_markdown_table_shows_fractional_means(self):
        row = dict(made_up_rows()[0], slots_missed=2.5)
        self.assertIn("| 2.5 |", experiment.markdown_table([row]))

    def test_plot_is_svg_with_two_panels_one_line_per_mode_and_a_legend(self):
        svg = experiment.plot_svg(made_up_rows(), experiment.ROBUST_MODES)
        root = ElementTree.fromstring(svg)
        self.assertEqual(root.tag, SVG_NS + "svg")
        panels = [g for g in root.iter(SVG_NS + "g") if g.get("class") == "panel"]
        self.assertEqual(len(panels), 2)
        for panel in panels:
            lines = [p for p in panel.iter(SVG_NS + "polyline")]
            self.assertEqual(sorted(p.get("data-name") for p in lines), ["maxmix", "none"])
            for line in lines:
                self.assertEqual(len(line.get("points").split()), 6)
        texts = [t.text for t in root.iter(SVG_NS + "text")]
        for label in ("corner RMSE (m)", "ID accuracy (%)", "ID error rate (%)", "Max-Mixture",
                      "no robust kernel", "40", "100"):
            self.assertIn(label, texts)

    def test_fig7_markdown_puts_the_maps_side_by_side(self):
        rows = [r for r in made_up_rows() if r["rate"] == 0.2]
        text = experiment.fig7_markdown(rows, 0.2, 1)
        self.assertIn("| map | ![none](fig7_none.svg) | ![maxmix](fig7_maxmix.svg) |", text)
        self.assertIn("ID accuracy", text)


class PlumbingTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.addCleanup(self.tmp.cleanup)
        self.fake = os.path.join(self.tmp.name, "parkslam")
        with open(self.fake, "w") as f:
            f.write(FAKE_PARKSLAM)
        os.chmod(self.fake, 0o755)
        self.out = os.path.join(self.tmp.name, "out")
        self.work = os.path.join(self.tmp.name, "work")
        os.environ.pop("FAKE_FAIL", None)
        self.addCleanup(os.environ.pop, "FAKE_FAIL", None)

    def read_csv(self):
        with open(os.path.join(self.out, "mapping_vs_id_errors.csv")) as f:
            return list(csv.DictReader(f))

    def test_dry_run_prints_every_command_and_runs_none(self):
        code, stdout, _ = run_main(["--dry-run", "--parkslam", "/no/such/parkslam",
                                    "--out", self.out])
        self.assertEqual(code, 0)
        lines = stdout.strip().splitlines()
        self.assertEqual(len(lines), 6 * 7 + 2)  # per rate: simulate + 2 x 3; two renders
        self.assertIn("/no/such/parkslam simulate --world default --seed 1 --out "
                      "WORK/r0.20/data --id-confusion-rate 0.12 --id-partial-rate 0.08", lines)
        self.assertIn("/no/such/parkslam map WORK/r0.05/data --out WORK/r0.05/none/map.json "
                      "--trajectory-out WORK/r0.05/none/trajectory.tum --robust none "
                      "--mode batch", lines)
        self.assertFalse(os.path.exists(self.out))

    def test_missing_binary_is_a_clear_error(self):
        code, _, stderr = run_main(["--parkslam", "/no/such/parkslam", "--out", self.out])
        self.assertEqual(code, 1)
        self.assertIn("parkslam binary not found", stderr)
        self.assertIn("/no/such/parkslam", stderr)

    def test_fig_rate_must_be_one_of_the_rates(self):
        code, _, stderr = run_main(["--parkslam", self.fake, "--fig-rate", "0.25"])
        self.assertEqual(code, 1)
        self.assertIn("--fig-rate", stderr)

    def test_full_run_writes_every_output(self):
        code, _, stderr = run_main(["--parkslam", self.fake, "--out", self.out,
                                    "--work", self.work])
        self.assertEqual(code, 0, stderr)
        for name in ("mapping_vs_id_errors.csv", "mapping_vs_id_errors.md",
                     "mapping_vs_id_errors.svg", "fig7_none.svg", "fig7_maxmix.svg", "fig7.md"):
            self.assertTrue(os.path.isfile(os.path.join(self.out, name)), name)
        records = self.read_csv()
        self.assertEqual(len(records), 12)
        by_key = {(r["id_error_rate"], r["robust"]): r for r in records}
        self.assertAlmostEqual(float(by_key["0.2", "none"]["slot_corner_rmse_m"]), 0.25)
        self.assertAlmostEqual(float(by_key["0.2", "maxmix"]["id_accuracy"]), 0.96)
        self.assertTrue(os.path.isfile(os.path.join(self.work, "r0.30", "maxmix", "map.json")))
        with open(os.path.join(self.out, "fig7.md")) as f:
            self.assertIn("ID error rate 20 %", f.read())

    def test_temporary_work_folder_is_removed(self):
        before = set(os.listdir(tempfile.gettempdir()))
        code, _, stderr = run_main(["--parkslam", self.fake, "--out", self.out, "--rates", "0,0.2"])
        self.assertEqual(code, 0, stderr)
        after = set(os.listdir(tempfile.gettempdir()))
        self.assertFalse({n for n in after - before if n.startswith("parkslam_mapping_")})

    def test_several_seeds_keep_per_seed_rows_and_add_means(self):
        code, _, stderr = run_main(["--parkslam", self.fake, "--out", self.out, "--work",
                                    self.work, "--seeds", "2", "--rates", "0,0.2", "--jobs", "2"])
        self.assertEqual(code, 0, stderr)
        seeds = [r["seed"] for r in self.read_csv()]
        self.assertEqual(seeds.count("1"), 4)
        self.assertEqual(seeds.count("2"), 4)
        self.assertEqual(seeds.count("mean"), 4)
        self.assertTrue(os.path.isdir(os.path.join(self.work, "r0.20", "seed2", "data")))
        with open(os.path.join(self.out, "mapping_vs_id_errors.md")) as f:
            self.assertIn("mean over 2 seeds", f.read())

    def test_failing_command_prints_it_with_its_stderr(self):
        os.environ["FAKE_FAIL"] = "eval-map"
        code, _, stderr = run_main(["--parkslam", self.fake, "--out", self.out, "--work",
                                    self.work])
        self.assertEqual(code, 1)
        self.assertIn(f"{self.fake} eval-map --map {self.work}/r0.00/maxmix/map.json", stderr)
        self.assertIn("boom: eval-map went wrong", stderr)
        self.assertFalse(os.path.exists(os.path.join(self.out, "mapping_vs_id_errors.csv")))


if __name__ == "__main__":
    unittest.main()
