#!/usr/bin/env python3
"""Tests of tools/plot_spectra.py: PNGs from real theory tables and simulated-looking
tables, legend text from metadata, and the error contract (exit 2, one line, no file).

Run: SLIDESPEC=build/slidespec python3 tests/tools/plot_spectra_test.py
Without SLIDESPEC the tests that need a theory table are skipped, saying so.
"""

import importlib.util
import math
import re
import os
import pathlib
import random
import subprocess
import sys
import tempfile
import unittest

import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402
import numpy as np  # noqa: E402

TOOL = pathlib.Path(__file__).resolve().parents[2] / "tools" / "plot_spectra.py"
SLIDESPEC = os.environ.get("SLIDESPEC")
NO_SLIDESPEC = "SLIDESPEC is not set: cannot generate theory tables (set it to the binary)"
PNG_SIZE = (750, 1050)  # rows, columns: 7 x 5 inches at 150 dpi
RUN_PNG_SIZE = (930, 1050)  # 7 x 6.2 inches: with the residual panel


def load_tool():
    spec = importlib.util.spec_from_file_location("plot_spectra", TOOL)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


plot_spectra = load_tool()


def run_tool(*arguments):
    return subprocess.run([sys.executable, str(TOOL), *map(str, arguments)],
                          capture_output=True, text=True, timeout=120)


def theory_table(directory, case):
    """A theory table from the real binary: `slidespec theory --case CASE`."""
    prefix = pathlib.Path(directory) / case
    subprocess.run([SLIDESPEC, "theory", "--case", case, "--out", str(prefix)], check=True,
                   capture_output=True, timeout=120)
    return prefix.with_suffix(".tsv")


def simulated_table(theory_path, out_path, extra_metadata=(), seed=1):
    """A simulated-looking table: theory times (1 + 0.05 gaussian), stderr 5 %, and the
    columns of `slidespec run` (written in a shuffled order: tools must go by name)."""
    generator = random.Random(seed)
    metadata, rows = [], []
    for line in theory_path.read_text().splitlines():
        if line.startswith("#"):
            if not line.startswith("# columns:"):
                metadata.append(line)
        elif line.startswith("omega"):
            continue
        else:
            omega, c_x, c_eq1 = map(float, line.split("\t"))
            noisy = c_x * (1 + 0.05 * generator.gauss(0, 1))
            rows.append({"omega": omega, "C_x": noisy, "stderr": 0.05 * noisy, "theory": c_x,
                         "n_avg": 64, "bandwidth": 0.1 * omega, "C_v": omega ** 2 * noisy,
                         "C_F": omega ** 4 * noisy, "C_eq1": c_eq1})
    metadata += [f"# {line}" for line in ("seed = 7", "realizations = 8", *extra_metadata)]
    names = ["theory", "omega", "stderr", "C_x", "n_avg", "bandwidth", "C_v", "C_F", "C_eq1"]
    body = ["\t".join(names)] + ["\t".join(f"{row[name]:.9e}" for name in names) for row in rows]
    out_path.write_text("\n".join(metadata + body) + "\n")
    return out_path


def spectrum(metadata, path="run.tsv"):
    return plot_spectra.Spectrum(path, dict(metadata), {})


class PictureTest(unittest.TestCase):
    def setUp(self):
        if not SLIDESPEC:
            self.skipTest(NO_SLIDESPEC)
        self.directory = tempfile.TemporaryDirectory()
        self.addCleanup(self.directory.cleanup)
        self.path = pathlib.Path(self.directory.name)

    def assert_picture(self, png, size=PNG_SIZE):
        """Exists, has the promised size, and holds a real drawing, not a blank canvas."""
        self.assertTrue(png.is_file(), f"{png} was not written")
        image = matplotlib.image.imread(png)
        self.assertEqual(image.shape[:2], size)
        colours = np.unique(image[:, :, :3].reshape(-1, 3), axis=0)
        self.assertGreater(len(colours), 50, "the picture looks blank")
        self.assertEqual([p.name for p in self.path.glob(".plot_spectra.*")], [],
                         "temporary file left behind")

    def test_theory_table_every_kind(self):
        table = theory_table(self.path, "reference")
        for kind in ("displacement", "velocity", "force"):
            png = self.path / f"theory_{kind}.png"
            result = run_tool(table, "-o", png, "--kind", kind, "--title", "reference case")
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assert_picture(png)

    def test_simulated_table_every_kind(self):
        table = simulated_table(theory_table(self.path, "reference"), self.path / "run.tsv",
                                ["case = reference", "complete = false"])
        for kind in ("displacement", "velocity", "force"):
            png = self.path / f"run_{kind}.png"
            result = run_tool(table, "-o", png, "--kind", kind)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assert_picture(png, RUN_PNG_SIZE)

    def test_overlay_of_three_files(self):
        files = [theory_table(self.path, "reference"),
                 simulated_table(theory_table(self.path, "fast"), self.path / "fast_run.tsv",
                                 ["case = fast"]),
                 theory_table(self.path, "many-contacts")]
        png = self.path / "overlay.png"
        result = run_tool(*files, "-o", png, "--labels", "reference,fast (run),N = 100",
                          "--omega-min", "0.3", "--omega-max", "3e4")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assert_picture(png, RUN_PNG_SIZE)

    def test_non_positive_values_are_skipped(self):
        table = simulated_table(theory_table(self.path, "reference"), self.path / "run.tsv")
        lines = table.read_text().splitlines()
        header = lines[[i for i, l in enumerate(lines) if l.startswith("theory")][0]].split("\t")
        for row in (-1, -2, -5):
            fields = lines[row].split("\t")
            fields[header.index("C_x")] = "0" if row == -1 else "-1e-30"
            fields[header.index("stderr")] = "nan"
            lines[row] = "\t".join(fields)
        table.write_text("\n".join(lines) + "\n")
        png = self.path / "gaps.png"
        result = run_tool(table, "-o", png)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assert_picture(png, RUN_PNG_SIZE)

    def test_format_from_the_extension(self):
        table = simulated_table(theory_table(self.path, "reference"), self.path / "run.tsv")
        for extension, magic in ((".png", b"\x89PNG\r\n"), (".pdf", b"%PDF-"), (".svg", b"<?xml")):
            out = self.path / f"run{extension}"
            result = run_tool(table, "-o", out)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertEqual(out.read_bytes()[:len(magic)], magic, extension)
        self.assertIn(b"<svg", (self.path / "run.svg").read_bytes()[:500])
        result = run_tool(table, "-o", self.path / "run.jpg")
        self.assertEqual(result.returncode, 2)
        self.assertIn(".jpg", result.stderr)
        self.assertFalse((self.path / "run.jpg").exists())

    def test_size_and_dpi(self):
        table = theory_table(self.path, "reference")
        png = self.path / "small.png"
        result = run_tool(table, "-o", png, "--size", "4x3", "--dpi", "100")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assert_picture(png, (300, 400))
        self.assertEqual(run_tool(table, "-o", png, "--size", "4by3").returncode, 2)

    def test_fine_theory_line_through_the_command_line(self):
        """`slidespec plot` recomputes the theory of a run on >= 64 points per decade: the
        drawn theory path (SVG group 'theory') has that many vertices over the run's band."""
        table = simulated_table(theory_table(self.path, "reference"), self.path / "run.tsv")
        svg = self.path / "run.svg"
        result = subprocess.run([SLIDESPEC, "plot", str(table), "-o", str(svg)],
                                capture_output=True, text=True, timeout=120)
        self.assertEqual(result.returncode, 0, result.stderr)
        text = svg.read_text()
        start = text.index('<g id="theory"')
        path = text[start:text.index("</g>", start)]
        vertices = len(re.findall(r"[ML]\s*-?[0-9.]+\s+-?[0-9.]+", path))
        decades = math.log10(1e5 / 0.1)
        self.assertGreaterEqual(vertices, 64 * decades, f"{vertices} vertices over {decades} decades")
        # Without the command line, the tool draws the table's own (coarse) theory column.
        coarse = self.path / "coarse.svg"
        self.assertEqual(run_tool(table, "-o", coarse).returncode, 0)
        coarse_text = coarse.read_text()
        start = coarse_text.index('<g id="theory"')
        coarse_path = coarse_text[start:coarse_text.index("</g>", start)]
        self.assertLess(len(re.findall(r"[ML]\s*-?[0-9.]+\s+-?[0-9.]+", coarse_path)), vertices)


class FigureTest(unittest.TestCase):
    """The parts of a figure, found by their gids in the matplotlib figure itself."""

    def setUp(self):
        if not SLIDESPEC:
            self.skipTest(NO_SLIDESPEC)
        self.directory = tempfile.TemporaryDirectory()
        self.addCleanup(self.directory.cleanup)
        self.path = pathlib.Path(self.directory.name)

    def render(self, *files, extra=()):
        args = plot_spectra.parse_arguments([*map(str, files), "-o", "x.png", *extra])
        spectra = [plot_spectra.read_spectrum(str(f)) for f in files]
        return plot_spectra.render(spectra, plot_spectra.legend_labels(spectra), args)

    def residual_axes(self, figure):
        return [a for a in figure.axes if a.get_gid() == plot_spectra.RESIDUAL_ID]

    def test_residual_panel_under_runs_only(self):
        theory = theory_table(self.path, "reference")
        run = simulated_table(theory, self.path / "run.tsv", ["case = reference"])
        figure = self.render(run)
        (panel,) = self.residual_axes(figure)
        self.assertEqual(panel.get_ylabel(), r"$C_x/\mathrm{theory} - 1$")
        self.assertTrue(panel.collections, "no +-2 stderr band")  # fill_between
        band = panel.collections[0].get_paths()[0].vertices[:, 1]
        self.assertGreater(band.max(), 0.09)  # 2 x the 5 % stderr of the synthetic run
        self.assertEqual(self.residual_axes(self.render(theory)), [])
        self.assertEqual(self.residual_axes(self.render(run, extra=["--no-residuals"])), [])

    def test_legend_names_simulation_and_theory_with_units(self):
        run = simulated_table(theory_table(self.path, "reference"), self.path / "run.tsv",
                              ["case = reference"])
        figure = self.render(run)
        texts = [t.get_text() for t in figure.axes[0].get_legend().get_texts()]
        self.assertIn("simulation, ±1 stderr", texts)
        self.assertIn("exact first-order theory", texts)
        self.assertIn(r"reference: N = 30, v = 0.5 mm/s, a = 1 mm, $\alpha$ = 1", texts)
        markers = [line for line in figure.axes[0].lines if line.get_gid() == "simulation"]
        self.assertEqual(len(markers), 1)
        self.assertEqual(markers[0].get_linestyle(), "None")  # points, not a line


    def test_omega_c_is_labelled_above_the_axes_and_below_the_title(self):
        theory = theory_table(self.path, "reference")
        figure = self.render(theory, extra=["--title", "a title"])
        plot_spectra.save_atomically(figure, str(self.path / "x.png"), 150)  # laid out, drawn
        axes = figure.axes[0]
        (label,) = [t for t in axes.texts if t.get_text() == r"$\omega_c$"]
        omega_c = plot_spectra.read_spectrum(str(theory)).number("omega_c")
        self.assertAlmostEqual(label.xy[0], math.log10(omega_c))
        renderer = figure.canvas.get_renderer()
        top_of_axes = axes.get_window_extent(renderer).y1
        label_box = label.get_window_extent(renderer)
        self.assertGreater(label_box.y0, top_of_axes)  # on the top edge, outside the data
        self.assertGreaterEqual(axes.title.get_window_extent(renderer).y0, label_box.y1)


    def test_a_spring_run_marks_its_resonance_and_has_no_eq1(self):
        prefix = self.path / "spring"
        subprocess.run([SLIDESPEC, "theory", "--set", "drive=spring", "--set", "k_drive=1e5", "--out",
                        str(prefix)], check=True, capture_output=True, timeout=120)
        theory = prefix.with_suffix(".tsv")
        figure = self.render(theory)
        axes = figure.axes[0]
        (label,) = [t for t in axes.texts if t.get_text() == r"$\omega_{\mathrm{res}}$"]
        resonance = plot_spectra.read_spectrum(str(theory)).number("omega_resonance")
        self.assertAlmostEqual(label.xy[0], math.log10(resonance))
        self.assertFalse([line for line in axes.lines if line.get_gid() == plot_spectra.EQ1_ID])


    def test_a_png_is_the_picture_matplotlibs_own_save_draws(self):
        run = simulated_table(theory_table(self.path, "reference"), self.path / "run.tsv",
                              ["case = reference"])
        plot_spectra.save_atomically(self.render(run), str(self.path / "ours.png"), 150)
        self.render(run).savefig(self.path / "theirs.png", dpi=150)
        ours = matplotlib.image.imread(self.path / "ours.png")
        theirs = matplotlib.image.imread(self.path / "theirs.png")
        self.assertTrue(np.array_equal(ours, theirs), "the one-pass layout moved something")


class LegendTest(unittest.TestCase):
    def test_parameters_take_the_tables_symbols_as_mathtext(self):
        # parameter_symbols.tsv holds parameters.def's symbols in the figures' markup.
        self.assertEqual(plot_spectra.parameter_text("eta0", "8000"), r"$\eta_0$ = 8000 1/s")
        self.assertEqual(plot_spectra.parameter_text("k_drive", "1e4"), r"$k_\mathrm{drive}$ = 1e4 N/m")
        self.assertEqual(plot_spectra.parameter_text("F_kin", "5"), r"$F_\mathrm{kin}$ = 5 N")
        self.assertEqual(plot_spectra.parameter_text("N_2", "5"), "N_2 = 5")  # a level's key as written
        self.assertLessEqual({"N", "eta1", "alpha", "touching"}, set(plot_spectra.PARAMETER_SYMBOLS))

    def test_label_metadata_wins(self):
        labels = plot_spectra.legend_labels([spectrum({"label": "rubber on concrete",
                                                       "case": "concrete-fit"})])
        self.assertEqual(labels, ["rubber on concrete"])

    def test_case_plus_differing_parameters(self):
        common = {"N": "30", "a": "0.001", "eta1": "33333333.3", "chain": "open"}
        reference = spectrum({**common, "case": "reference", "v": "0.00050000000000000001"})
        fast = spectrum({**common, "case": "fast", "v": "5e-3", "eta1": "3333333.3"})
        self.assertEqual(plot_spectra.legend_labels([reference, fast]),
                         ["reference: v = 0.5 mm/s", "fast: v = 5 mm/s"])

    def test_set_keys_are_named_with_symbols(self):
        labels = plot_spectra.legend_labels([
            spectrum({"case": "reference", "label": "reference + N=5, alpha=3", "N": "5",
                      "alpha": "3", "a": "1e-4"}),
            spectrum({"case": "reference", "N": "30", "alpha": "1", "a": "1e-4"})])
        self.assertEqual(labels, [r"reference: N = 5, $\alpha$ = 3", r"reference: N = 30, $\alpha$ = 1"])

    def test_equal_numbers_written_differently_do_not_differ(self):
        labels = plot_spectra.legend_labels([spectrum({"case": "reference", "v": "5e-4"}),
                                             spectrum({"case": "again", "v": "0.0005"})])
        self.assertEqual(labels, ["reference", "again"])

    def test_a_sweeps_combined_table_is_one_series_per_run(self):
        with tempfile.TemporaryDirectory() as folder:
            path = pathlib.Path(folder) / "sweep.tsv"
            path.write_text("# slidespec 0.1.0 sweep: 2 runs\n"
                            "# sweep_renewal = poisson periodic  # its column holds the index\n"
                            "# sweep_N = 10 30\n"
                            "# run_0 = reference + N=10  # a.tsv\n"
                            "# run_1 = reference + renewal=periodic, N=30  # b.tsv\n"
                            "# run\trenewal\tN\tomega\tC_x\tstderr\ttheory\n"
                            "0\t0\t10\t1\t2\t0.1\t2\n0\t0\t10\t10\t1\t0.1\t1\n"
                            "1\t1\t30\t1\t3\t0.1\t3\n1\t1\t30\t10\t2\t0.1\t2\n")
            runs = plot_spectra.split_runs(plot_spectra.read_spectrum(str(path)))
        self.assertEqual(len(runs), 2)
        self.assertEqual([list(r.columns["C_x"]) for r in runs], [[2, 1], [3, 2]])
        self.assertEqual([r.metadata["renewal"] for r in runs], ["poisson", "periodic"])
        self.assertEqual(plot_spectra.legend_labels(runs),
                         ["reference: N = 10, renewal = poisson", "reference: N = 30, renewal = periodic"])

    def test_file_name_without_case(self):
        labels = plot_spectra.legend_labels([spectrum({}, "/some/dir/ref.tsv")])
        self.assertEqual(labels, ["ref.tsv"])

    def test_incomplete_runs_are_marked(self):
        labels = plot_spectra.legend_labels([spectrum({"case": "fast", "complete": "false"}),
                                             spectrum({"label": "mine", "complete": "false"}),
                                             spectrum({"case": "reference", "complete": "true"})])
        self.assertEqual(labels, ["fast (incomplete)", "mine (incomplete)", "reference"])

    def test_metadata_parsing_strips_trailing_comments(self):
        with tempfile.TemporaryDirectory() as directory:
            path = pathlib.Path(directory) / "t.tsv"
            path.write_text("# slidespec 0.1.0\n# omega_c = 5.4e+02  # sqrt(N k0/M) [rad/s]\n"
                            "# label = run #3\n# columns: omega, C_x\nC_x\tomega\n2e-20\t1\n")
            parsed = plot_spectra.read_spectrum(str(path))
        self.assertEqual(parsed.metadata, {"omega_c": "5.4e+02", "label": "run #3"})
        self.assertEqual(parsed.columns["C_x"].tolist(), [2e-20])


class MeasuredFigureTest(unittest.TestCase):
    """`slidespec analyze` tables of the measured basalt and sepiolite records (tests/data):
    the observable on the axis, a fit's residual panel, a failed fit marked FAILED in the
    legend, and a sensor floor drawn only when one was given or fitted."""

    DATA = pathlib.Path(__file__).resolve().parents[1] / "data" / "realdata"

    def setUp(self):
        if not SLIDESPEC:
            self.skipTest(NO_SLIDESPEC)
        self.directory = tempfile.TemporaryDirectory()
        self.addCleanup(self.directory.cleanup)
        self.path = pathlib.Path(self.directory.name)

    def analyze(self, record, *options):
        prefix = self.path / "analysis"
        subprocess.run([SLIDESPEC, "analyze", str(self.DATA / record), *options, "--no-plot", "--out",
                        str(prefix)], capture_output=True, timeout=300)
        table = plot_spectra.read_spectrum(str(prefix.with_suffix(".tsv")))
        args = plot_spectra.parse_arguments([str(prefix) + ".tsv", "-o", "x.png"])
        figure = plot_spectra.render([table], plot_spectra.legend_labels([table]), args)
        return figure, [t.get_text() for t in figure.axes[0].get_legend().get_texts()]

    def test_a_good_fit_has_residuals_and_its_fitted_floor(self):
        figure, texts = self.analyze("velstep4_BRAVA_expb819_basalt.txt", "--window", "11608:11674",
                                     "--fit", "power-law")
        panels = [a for a in figure.axes if a.get_gid() == plot_spectra.RESIDUAL_ID]
        self.assertEqual(len(panels), 1)
        self.assertEqual(panels[0].get_ylabel(), r"$(C - \mathrm{fit})/\sigma$")
        self.assertIn("sensor floor (fitted)", texts)
        self.assertNotIn("sensor floor; hollow: at or below it", texts)
        self.assertFalse(any("FAILED" in t for t in texts), texts)
        self.assertIn("displacement", figure.axes[0].get_ylabel())

    def test_a_failed_fit_is_marked_in_the_legend(self):
        _, texts = self.analyze("velstep3_TR2_exp013_sepiolite.txt", "--window", "21350:22319",
                                "--fit", "power-law")
        self.assertTrue(any(t.startswith("fit FAILED") for t in texts), texts)

    def test_a_force_spectrum_says_so_and_draws_no_floor(self):
        figure, texts = self.analyze("velstep4_BRAVA_expb819_basalt.txt", "--window", "11608:11674",
                                     "--observable", "force", "--contact-area", "25cm2")
        self.assertIn("C_F", figure.axes[0].get_ylabel())
        self.assertFalse(any("floor" in t for t in texts), texts)


class ErrorTest(unittest.TestCase):
    """Every unusable input: exit status 2, one line on stderr naming file and problem,
    and no output file (nor a temporary one) left behind."""

    def setUp(self):
        self.directory = tempfile.TemporaryDirectory()
        self.addCleanup(self.directory.cleanup)
        self.path = pathlib.Path(self.directory.name)
        self.good = self.path / "good.tsv"
        self.good.write_text("# v = 5e-4\nomega\tC_x\n1\t1e-10\n10\t1e-14\n")

    def assert_refused(self, bad, problem):
        png = self.path / "out.png"
        result = run_tool(self.good, bad, "-o", png)
        self.assertEqual(result.returncode, 2, result.stderr)
        lines = result.stderr.splitlines()
        self.assertEqual(len(lines), 1, result.stderr)
        self.assertIn(str(bad), lines[0])
        self.assertIn(problem, lines[0])
        self.assertEqual(list(self.path.glob("*.png")) + list(self.path.glob(".plot*")), [])

    def test_missing_file(self):
        self.assert_refused(self.path / "absent.tsv", "cannot read")

    def test_no_c_x_column(self):
        bad = self.path / "no_cx.tsv"
        bad.write_text("# N = 30\nomega\tC_v\n1\t2\n")
        self.assert_refused(bad, "no 'C_x' column")

    def test_text_in_a_number(self):
        bad = self.path / "text.tsv"
        bad.write_text("omega\tC_x\n1\t1e-10\n10\tabc\n")
        self.assert_refused(bad, "line 3: 'abc' is not a number")

    def test_rows_without_a_column_line(self):
        # A CSV's rows hold no tab: neither row is a column line, and the first is named.
        bad = self.path / "commas.tsv"
        bad.write_text("1,2,3\n4,5,6\n")
        self.assert_refused(bad, "line 1: '1,2,3' is not a number (a table's fields are separated by tabs)")

    def test_nothing_in_the_omega_range(self):
        png = self.path / "out.png"
        result = run_tool(self.good, "-o", png, "--omega-min", "1e3")
        self.assertEqual(result.returncode, 2)
        self.assertEqual(result.stderr.splitlines(),
                         ["plot_spectra: nothing to plot: no positive values in the omega range"])
        self.assertFalse(png.exists())

    def test_a_figure_that_cannot_be_written_is_a_failure(self):
        """Good inputs whose figure cannot be saved exit 1 (a failure), not 2 (bad input)."""
        png = self.path / "absent_folder" / "out.png"
        result = run_tool(self.good, "-o", png)
        self.assertEqual(result.returncode, 1, result.stderr)
        self.assertEqual(len(result.stderr.splitlines()), 1, result.stderr)
        self.assertIn("cannot write", result.stderr)
        self.assertIn(str(png), result.stderr)

    def test_force_without_mass(self):
        png = self.path / "out.png"
        result = run_tool(self.good, "-o", png, "--kind", "force")
        self.assertEqual(result.returncode, 2)
        self.assertIn("no 'M' metadata", result.stderr)
        self.assertFalse(png.exists())


if __name__ == "__main__":
    if not SLIDESPEC:
        print(f"plot_spectra_test: {NO_SLIDESPEC}", file=sys.stderr)
    unittest.main()
