"""The optimiser task panel (GUI only; the logic is :mod:`.optimiser`, headless).

Five boxes in FreeCAD's task view:

1. **Problem** — the objective (those the cam's optimiser serves:
   :func:`.optimiser.objective_choices`) and the design variables (check boxes from
   :func:`.optimiser.variable_choices`: only those that mean something for this cam; a parallel
   indexer's C, R_p and r_r checked and fixed — its optimiser varies all three —, with a note);
2. **Bounds** — the base radius' lower bound first and in bold: the design checks do not bound
   the cam from below (with R_b free the optimiser runs to this bound), so the user must give
   the real limit (shaft, hub, bore); then R_b's upper bound and |e|'s (a parallel indexer: the
   bounds of C, R_p and r_r, its optimiser's own, in words);
3. **Algorithm** — gradient (SLSQP, MMA, CCSAQ), derivative-free (COBYLA, BOBYQA), global
   (ISRES; random multistarts) with the seed, and the evaluation budget (a parallel indexer:
   :func:`.optimiser.algorithm_choices`, derivative-free, no restarts);
4. **Run** — Run / Cancel, a progress bar, the live objective and largest constraint
   violation, and the convergence plot (matplotlib, when FreeCAD's Python has it);
5. **Result** — the figures before and after, every design check before and after, and Apply.

The run is an :class:`.optimiser.OptimiseJob` (a worker thread); a ``QTimer`` in the GUI
thread reads its progress every 100 ms, so FreeCAD never waits for the optimiser.  Cancel sets
the library's ``threading.Event`` (the run stops at the next evaluation).  **Apply** writes the
optimised spec — design and the ``[optimise]`` settings used — as one undo step; a result that
fails the dense re-check is applied only after the user confirms.  **Close** writes nothing
(and cancels a run in progress).  Starting values come from the feature's ``Optimise``
properties (the spec's ``[optimise]`` section).
"""
from __future__ import annotations

import time
from typing import Any

import FreeCAD
import FreeCADGui
import numpy as np
from PySide import QtCore, QtGui  # FreeCAD's PySide shim (PySide2 in 0.20, PySide6 in 1.x)

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.optimise.objectives import UNITS

from . import optimiser as opt
from . import properties as props
from .check_design import _AMBER, _GREEN, _RED
from .qt_compat import fit_task_width, standard_buttons

POLL_MS = 100
PLOT_EVERY_S = 1.0
_PANELS: list[Any] = []   # the open panel (for tests and scripts)


class OptimiserPanel:
    """The task panel for one cam (``FreeCADGui.Control.showDialog(panel)``)."""

    def __init__(self, obj: Any):
        self.obj = obj
        self.spec = props.spec_of(obj)        # raises SpecError: the command reports it
        self.units = self.spec.units
        self.defaults = opt.settings_of(self.spec)
        self.job: opt.OptimiseJob | None = None
        self.result: Any = None
        self.applied = False
        self.ticks: list[float] = []          # GUI-thread timer ticks during a run (responsiveness)
        self.plot_seconds: list[float] = []   # time of each redraw of the convergence plot
        self._last_plot = 0.0

        problem, bounds, algo = self._problem_box(), self._bounds_box(), self._algorithm_box()
        runbox, resbox = self._run_box(), self._result_box()
        self.form = [problem, bounds, algo, runbox, resbox]
        for w in self.form:
            fit_task_width(w)
        self.settings_widgets = [problem, bounds, algo]
        self._timer = QtCore.QTimer(runbox)
        self._timer.setInterval(POLL_MS)
        self._timer.timeout.connect(self._poll)
        # closed without Close (another task panel, the document closed): stop the run too
        runbox.destroyed.connect(lambda *_: self._abandon())
        self._vars_touched = False
        self.objective.currentIndexChanged.connect(lambda *_: self._objective_changed())
        self.algorithm.currentIndexChanged.connect(lambda *_: self.refresh())
        for cb in self.var_boxes.values():
            cb.clicked.connect(lambda *_: self._vars_clicked())
            cb.toggled.connect(lambda *_: self.refresh())
        for spin in (self.rb_max, self.e_max, self.max_evals, self.multistart, self.seed):
            if spin is None:
                continue
            spin.valueChanged.connect(lambda *_: self.refresh())
        if self.rb_min is not None:
            self.rb_min.valueChanged.connect(lambda *_: self._rb_min_edited())
        self.refresh()

    # -- the five boxes
    def _problem_box(self) -> Any:
        """1. Problem: the objective, the design variables' check boxes and the status line."""
        problem = QtGui.QWidget()
        problem.setObjectName("OptimiseProblem")
        problem.setWindowTitle(f"Optimise {self.obj.Label}")
        pl = QtGui.QVBoxLayout(problem)
        form = QtGui.QFormLayout()
        self.objective = QtGui.QComboBox()
        objectives = opt.objective_choices(self.spec)
        for name in objectives:
            self.objective.addItem(opt.OBJECTIVE_LABELS[name], name)
        self.objective.setCurrentIndex(objectives.index(self.defaults.objective)
                                       if self.defaults.objective in objectives else 0)
        self.objective.setToolTip(props.field_tooltip("optimise.objective"))
        form.addRow("Objective:", self.objective)
        pl.addLayout(form)
        vbox = QtGui.QGroupBox("Design variables")
        vl = QtGui.QVBoxLayout(vbox)
        self.var_boxes: dict[str, Any] = {}
        #: the variables the cam's optimiser always varies (a parallel indexer's): checked, not to uncheck
        self.fixed_tokens: set[str] = set()
        chosen = opt.selected_tokens(self.spec)
        for c in opt.variable_choices(self.spec):
            cb = QtGui.QCheckBox(f"{c.label}" + (f"  ({c.count})" if c.count > 1 else ""))
            cb.setChecked(c.token in chosen or c.fixed)
            cb.setToolTip(c.reason or f"optimise.variables token: {c.token}")
            if c.fixed:
                self.fixed_tokens.add(c.token)
            vl.addWidget(cb)
            self.var_boxes[c.token] = cb
        self.var_count = QtGui.QLabel()
        vl.addWidget(self.var_count)
        note = opt.fixed_variables_note(self.spec)
        self.var_note = QtGui.QLabel(note)    # why the fixed ones cannot be unchecked
        self.var_note.setObjectName("FixedVariables")
        self.var_note.setWordWrap(True)
        self.var_note.setVisible(bool(note))
        vl.addWidget(self.var_note)
        pl.addWidget(vbox)
        self.status = QtGui.QLabel()      # what the choices amount to, or the rule they break
        self.status.setWordWrap(True)
        self.status.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        pl.addWidget(self.status)
        return problem

    def _bounds_box(self) -> Any:
        """2. Bounds: the base radius' lower bound first and in bold, then R_b's upper bound and |e|'s
        (a cam whose optimiser takes no R_b bound, a parallel indexer: its variables' own bounds, in words)."""
        bounds = QtGui.QWidget()
        bounds.setObjectName("OptimiseBounds")
        bounds.setWindowTitle("Bounds")
        bl = QtGui.QVBoxLayout(bounds)
        self._rb_min_default = opt.bound_is_default(self.spec)
        if self.defaults.base_radius_min is None:
            self.rb_min = self.rb_max = self.e_max = self.rb_min_box = self.rb_note = None
            self.bounds_note = QtGui.QLabel(opt.own_bounds_note(self.spec)
                                            or "The cam's optimiser sets its variables' bounds itself.")
            self.bounds_note.setObjectName("OwnBounds")
            self.bounds_note.setWordWrap(True)
            bl.addWidget(self.bounds_note)
            return bounds
        self.rb_min = self._length_spin(self.defaults.base_radius_min)
        self.rb_max = self._length_spin(self.defaults.base_radius_max)
        # an oscillating arm has no offset: no |e| bound (its position bounds are the Optimise properties)
        self.e_max = (self._length_spin(self.defaults.offset_max) if self.defaults.offset_max is not None
                      else None)
        self.rb_min_box = QtGui.QGroupBox("Smallest base radius R_b (shaft, hub, bore)")
        self.rb_min_box.setObjectName("BaseRadiusMin")
        self.rb_min_box.setStyleSheet("QGroupBox { font-weight: bold; }")
        rl = QtGui.QVBoxLayout(self.rb_min_box)
        row = QtGui.QHBoxLayout()
        row.addWidget(QtGui.QLabel("R_b ≥"))
        row.addWidget(self.rb_min, 1)
        rl.addLayout(row)
        self.rb_note = QtGui.QLabel()
        self.rb_note.setWordWrap(True)
        self.rb_note.setStyleSheet("font-weight: normal;")
        rl.addWidget(self.rb_note)
        bl.addWidget(self.rb_min_box)
        bform = QtGui.QFormLayout()
        bform.addRow("Largest R_b:", self.rb_max)
        if self.e_max is not None:
            bform.addRow("Largest |e|:", self.e_max)
        bl.addLayout(bform)
        for spin, field in ((self.rb_min, "base_radius_min"), (self.rb_max, "base_radius_max"),
                            (self.e_max, "offset_max")):
            if spin is None:
                continue
            spin.setToolTip(props.field_tooltip(f"optimise.{field}"))
        return bounds

    def _algorithm_box(self) -> Any:
        """3. Algorithm: the algorithm, the evaluation budget, the random restarts and the seed."""
        algo = QtGui.QWidget()
        algo.setObjectName("OptimiseAlgorithm")
        algo.setWindowTitle("Algorithm")
        af = QtGui.QFormLayout(algo)
        self.algorithm = QtGui.QComboBox()
        for name in opt.algorithm_choices(self.spec):
            self.algorithm.addItem(opt.algorithm_label(self.spec, name), name)
        self.algorithm.setCurrentIndex(max(self.algorithm.findData(self.defaults.algorithm), 0))
        self.algorithm.setToolTip(props.field_tooltip("optimise.algorithm"))
        af.addRow("Algorithm:", self.algorithm)
        self.max_evals = QtGui.QSpinBox()
        self.max_evals.setRange(10, 10_000_000)
        self.max_evals.setValue(self.defaults.max_evaluations)
        self.max_evals.setToolTip(props.field_tooltip("optimise.max_evaluations"))
        af.addRow("Max evaluations:", self.max_evals)
        self.multistart = QtGui.QSpinBox()
        offered = opt.multistart_offered(self.spec)
        self.multistart.setRange(0, 1000 if offered else 0)
        self.multistart.setValue(self.defaults.multistart)
        self.multistart.setEnabled(offered)
        self.multistart.setToolTip(props.field_tooltip("optimise.multistart") if offered else
                                   "no random restarts: this cam's optimiser runs from its design alone")
        af.addRow("Random restarts:", self.multistart)
        self.seed = QtGui.QSpinBox()
        self.seed.setRange(0, 2**31 - 1)
        self.seed.setValue(self.defaults.seed)
        self.seed.setToolTip(props.field_tooltip("optimise.seed") if offered else
                             "no random starts: this cam's optimiser is deterministic")
        self.seed.setEnabled(offered)
        af.addRow("Seed:", self.seed)
        return algo

    def _run_box(self) -> Any:
        """4. Run: Run / Cancel, the progress bar, the live figures and the convergence plot."""
        runbox = QtGui.QWidget()
        runbox.setObjectName("OptimiseRun")
        runbox.setWindowTitle("Run")
        rl2 = QtGui.QVBoxLayout(runbox)
        buttons = QtGui.QHBoxLayout()
        self.run_button = QtGui.QPushButton("Run")
        self.cancel_button = QtGui.QPushButton("Cancel run")
        self.cancel_button.setEnabled(False)
        self.run_button.clicked.connect(self.start)
        self.cancel_button.clicked.connect(self.cancel)
        buttons.addWidget(self.run_button)
        buttons.addWidget(self.cancel_button)
        rl2.addLayout(buttons)
        self.progress = QtGui.QProgressBar()
        self.progress.setRange(0, 1)
        self.progress.setValue(0)
        self.progress.setFormat("%v / %m evaluations")
        rl2.addWidget(self.progress)
        self.live = QtGui.QLabel("Not run yet.")
        self.live.setWordWrap(True)
        self.live.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        rl2.addWidget(self.live)
        self.canvas = self._make_canvas()
        if self.canvas is not None:
            rl2.addWidget(self.canvas)
        return runbox

    def _result_box(self) -> Any:
        """5. Result: the verdict, the figures and the checks before → after, and Apply."""
        resbox = QtGui.QWidget()
        resbox.setObjectName("OptimiseResult")
        resbox.setWindowTitle("Result: before → after")
        self.result_layout = QtGui.QVBoxLayout(resbox)
        self.verdict = QtGui.QLabel("Run the optimiser to compare the design before and after.")
        self.verdict.setWordWrap(True)
        self.verdict.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        self.result_layout.addWidget(self.verdict)
        self.figure_table = self._table("figures", ["quantity", "before", "after"])
        self.check_table = self._table("check_comparison", ["check", "limit", "before", "after"])
        self.result_layout.addWidget(self.figure_table)
        self.result_layout.addWidget(self.check_table)
        self.figure_table.setVisible(False)
        self.check_table.setVisible(False)
        self.apply_button = QtGui.QPushButton("Apply to the cam")
        self.apply_button.setEnabled(False)
        self.apply_button.clicked.connect(self.apply)
        self.result_layout.addWidget(self.apply_button)
        return resbox

    # -- widgets
    def _length_spin(self, value: float) -> Any:
        spin = QtGui.QDoubleSpinBox()
        spin.setDecimals(5 if self.units == "in" else 4)
        spin.setRange(0.0, 1e6)
        spin.setSingleStep(0.05 if self.units == "in" else 1.0)
        spin.setSuffix(f" {self.units}")
        spin.setValue(value)
        return spin

    def _table(self, name: str, headers: list[str]) -> Any:
        t = QtGui.QTableWidget(0, len(headers))
        t.setObjectName(name)
        t.setHorizontalHeaderLabels(headers)
        t.verticalHeader().setVisible(False)
        t.setEditTriggers(QtGui.QAbstractItemView.NoEditTriggers)
        t.verticalHeader().setDefaultSectionSize(t.fontMetrics().height() + 8)
        t.horizontalHeader().setStretchLastSection(True)
        return t

    def _make_canvas(self) -> Any:
        try:
            # deferred: matplotlib (optional in FreeCAD's Python; slow to import)
            from matplotlib.figure import Figure
            try:
                # deferred: matplotlib (its Qt canvas)
                from matplotlib.backends.backend_qtagg import FigureCanvasQTAgg
            except ImportError:
                # deferred: matplotlib (older matplotlib: the Qt5 canvas)
                from matplotlib.backends.backend_qt5agg import FigureCanvasQTAgg
        except ImportError:
            return None  # no matplotlib in FreeCAD's Python: the numbers are shown all the same
        fig = Figure(figsize=(4.6, 3.2), dpi=90)
        fig.subplots_adjust(left=0.13, right=0.98, top=0.93, bottom=0.12, hspace=0.3)
        self.ax_obj, self.ax_viol = fig.subplots(2, 1, sharex=True)
        self.ax_viol.set_yscale("log")
        self.ax_obj.set_title("objective", fontsize=8, loc="left")
        self.ax_viol.set_title("largest constraint value (≤ 0 feasible, drawn at 1e-9)", fontsize=8, loc="left")
        self.ax_viol.set_xlabel("evaluation", fontsize=7)
        for a in (self.ax_obj, self.ax_viol):
            a.tick_params(labelsize=7)
            a.grid(True, lw=0.3, alpha=0.6)
        self._lines: dict[str, Any] = {}
        canvas = FigureCanvasQTAgg(fig)
        canvas.setMinimumHeight(260)
        canvas.setObjectName("convergence")
        self.fig = fig
        self._draw_plot([])
        return canvas

    # -- settings
    def tokens(self) -> set[str]:
        """The chosen variables: the enabled, checked boxes and the fixed ones."""
        return {t for t, cb in self.var_boxes.items()
                if cb.isChecked() and (cb.isEnabled() or t in self.fixed_tokens)}

    def settings(self) -> opt.Settings:
        """The panel's choices (variables from the enabled, checked boxes)."""
        objective = self.objective.currentData()
        return opt.Settings(objective=objective,
                            variables=opt.variables_text(self.spec, self.tokens(), objective),
                            algorithm=self.algorithm.currentData(), max_evaluations=self.max_evals.value(),
                            multistart=self.multistart.value(), seed=self.seed.value(),
                            base_radius_min=self.rb_min.value() if self.rb_min is not None else None,
                            base_radius_max=self.rb_max.value() if self.rb_max is not None else None,
                            offset_max=self.e_max.value() if self.e_max is not None else None)

    def _vars_clicked(self) -> None:
        self._vars_touched = True

    def _objective_changed(self) -> None:
        """A new objective: while the user has not picked variables, select what the spec's
        ``optimise.variables`` means for it ("auto" adds the blank orientation for the
        machining time)."""
        if not self._vars_touched:
            objective = self.objective.currentData()
            chosen = opt.selected_tokens(self.spec.replace(**{"optimise.objective": objective,
                                                              "optimise.algorithm": "auto"}))
            for token, cb in self.var_boxes.items():
                cb.blockSignals(True)
                cb.setChecked(token in chosen)
                cb.blockSignals(False)
        self.refresh()

    def _rb_min_edited(self) -> None:
        self._rb_min_default = False
        self.refresh()

    def refresh(self) -> Any:
        """Enable what applies, describe the R_b bound, validate; returns the run spec or None."""
        objective = self.objective.currentData()
        choices = {c.token: c for c in opt.variable_choices(self.spec, objective)}
        for token, cb in self.var_boxes.items():
            cb.setEnabled(choices[token].enabled and not choices[token].fixed)
        smooth = objective not in opt.NON_SMOOTH
        model = self.algorithm.model()
        for i in range(self.algorithm.count()):
            item = model.item(i) if isinstance(model, QtGui.QStandardItemModel) else None
            if item is not None:
                item.setEnabled(smooth or self.algorithm.itemData(i) not in opt.GRADIENT_ALGORITHMS)
        tokens = self.tokens()
        n = sum(choices[t].count for t in tokens)
        self.var_count.setText(f"{n} design variable{'s' if n != 1 else ''}"
                               + (" (all fixed: varied together)" if tokens and tokens <= self.fixed_tokens else ""))
        for spin, token in ((self.rb_min, "base_radius"), (self.rb_max, "base_radius"), (self.e_max, "offset")):
            if spin is not None:
                spin.setEnabled(token in tokens)
        if self.rb_note is None:      # no R_b bound to describe (a parallel indexer)
            pass
        elif self._rb_min_default:
            self.rb_note.setText(
                f"Shown: the library's default (½ × the initial R_b = {self.spec.cam.base_radius:g} {self.units}, "
                f"at least 1.05 × (roller + bore radius)) — not a real limit. The design checks do not bound "
                f"the cam from below: with R_b free the optimiser runs to this bound. Enter the smallest R_b "
                f"your shaft, hub and bore allow.")
            self.rb_note.setStyleSheet(f"font-weight: normal; color: {_AMBER};")
        else:
            stored = self.spec.optimise.base_radius_min
            given = ("from the cam's OptimiseBaseRadiusMin property"
                     if stored is not None and abs(self.rb_min.value() - stored) <= 1e-9 * stored else "your limit")
            self.rb_note.setText(f"R_b will not go below this ({given}). The design checks do not bound the "
                                 "cam from below: with R_b free the optimiser usually ends on this bound.")
            self.rb_note.setStyleSheet("font-weight: normal;")
        spec = None
        try:
            if not tokens:
                raise SpecError("optimise.variables", "choose at least one design variable")
            spec = opt.run_spec(self.spec, self.settings())
        except SpecError as exc:
            self._say(f"{props.describe_field(exc.field)}: {exc.rule}", _RED)
        else:
            self._say(f"Ready: {objective} over {n} variable{'s' if n != 1 else ''}.", _GREEN)
        running = self.job is not None and self.job.running
        self.run_button.setEnabled(spec is not None and not running)
        return spec

    def _say(self, text: str, colour: str = "") -> None:
        self.status.setText(text)
        self.status.setStyleSheet(f"color: {colour}" if colour else "")

    # -- running
    @property
    def running(self) -> bool:
        return self.job is not None and self.job.running

    def start(self) -> bool:
        """Start a run with the current choices (False, with the reason shown, if they are bad)."""
        if self.running:
            return False
        spec = self.refresh()
        if spec is None:
            return False
        why = opt.changed_since(self.obj, self.spec)
        if why is not None:
            self._say(f"{why} since this panel opened: close it and open it again", _RED)
            return False
        self.result = None
        self.job = opt.OptimiseJob(spec)
        self._show_result(None)
        cfg = spec.optimise
        budget = cfg.max_evaluations * (1 + cfg.multistart)
        self.progress.setRange(0, budget)
        self.progress.setValue(0)
        self.live.setText("starting …")
        self.live.setStyleSheet("")
        self.ticks = []
        self._draw_plot([])
        for w in self.settings_widgets:
            w.setEnabled(False)
        self.run_button.setEnabled(False)
        self.cancel_button.setEnabled(True)
        self.apply_button.setEnabled(False)
        FreeCAD.Console.PrintMessage(f"{self.obj.Label}: optimising {cfg.objective} over "
                                     f"{cfg.variables} ({cfg.algorithm}, at most {budget} evaluations)\n")
        self._say("Running: the settings are locked until the run ends or is cancelled.", "")
        self.job.start()
        self._timer.start()
        self.scroll_to(self.form[3])
        return True

    def cancel(self) -> None:
        """Stop the run at its next evaluation (the library's cancel event)."""
        if self.running:
            self.job.cancel()
            self.cancel_button.setEnabled(False)
            self.live.setText(self.live.text() + "\ncancelling at the next evaluation …")

    def _poll(self) -> None:
        self.ticks.append(time.perf_counter())
        job = self.job
        if job is None:
            self._timer.stop()
            return
        p = job.latest
        if p is not None:
            # the budget is per solve: a re-solve with finer windows (refine_rounds) may exceed it
            top = max(p.budget, p.evaluations)
            if top != self.progress.maximum():
                self.progress.setRange(0, top)
            self.progress.setValue(p.evaluations)
            self.live.setText(self._live_text(p, job))
            self.live.setStyleSheet(f"color: {_GREEN}" if p.max_violation <= 0 else "")
            now = time.perf_counter()
            if now - self._last_plot >= PLOT_EVERY_S:
                self._last_plot = now
                self._draw_plot(list(job.history))
        if job.done:
            self._timer.stop()
            self._finished()

    def _live_text(self, p: Any, job: opt.OptimiseJob) -> str:
        unit = self._phase_unit(p.phase, job.spec.optimise.objective)
        best = "none yet" if p.best is None else f"{p.best:.6g} {unit}"
        what = p.phase.split(" on ", 1)[1].split()[0] if " on " in p.phase else job.spec.optimise.objective
        obj = "—" if p.objective != p.objective else f"{p.objective:.6g}"
        feas = "feasible" if p.max_violation <= 0 else "infeasible"
        secs = time.perf_counter() - job.started
        return (f"{p.phase}: evaluation {p.evaluations} of ≤ {p.budget}, {secs:.1f} s\n"
                f"{what} {obj} {unit}; best feasible: {best}\n"
                f"largest constraint value {p.max_violation:+.3e} ({feas}; ≤ 0 is feasible)")

    def _unit(self, objective: str) -> str:
        return UNITS[objective].replace("length", self.units)

    def _phase_unit(self, phase: str, objective: str) -> str:
        """The unit of what a phase minimises ("slsqp on thesis_length": the smooth stand-in)."""
        name = phase.split(" on ", 1)[1].split()[0] if " on " in phase else objective
        return self._unit(name if name in UNITS else objective)

    def _finished(self) -> None:
        job = self.job
        for w in self.settings_widgets:
            w.setEnabled(True)
        self.cancel_button.setEnabled(False)
        self.refresh()
        self._draw_plot(list(job.history))
        if job.error is not None:
            self.live.setText(f"The optimiser stopped with an error: {job.error}")
            self.live.setStyleSheet(f"color: {_RED}")
            FreeCAD.Console.PrintError(f"{self.obj.Label}: optimise: {job.error}\n")
            return
        res = self.result = job.result
        self.progress.setRange(0, max(res.evaluations, 1))
        self.progress.setValue(res.evaluations)
        unit = self._unit(res.objective)
        what = f"{res.objective} ({opt.result_objective_label(res)})"
        self.live.setText(f"{res.status_text}: {what} {res.initial_value:.6g} → {res.value:.6g} {unit} in "
                          f"{res.evaluations} evaluations, {res.time_s:.1f} s\n{res.message}")
        self.live.setStyleSheet("")
        self._show_result(res)
        self.scroll_to(self.form[4])
        out = FreeCAD.Console.PrintMessage if res.feasible else FreeCAD.Console.PrintWarning
        out(f"{self.obj.Label}: optimise {res.status_text}: {what} {res.initial_value:.6g} → "
            f"{res.value:.6g} {unit} in {res.evaluations} evaluations; "
            + ("every design check passes" if res.feasible else
               f"the result FAILS the dense re-check: {', '.join(res.checks.failed)}") + "\n")

    # -- results
    def _show_result(self, res: Any) -> None:
        self.figure_table.setVisible(res is not None)
        self.check_table.setVisible(res is not None)
        if res is None:
            self.figure_table.setRowCount(0)
            self.check_table.setRowCount(0)
            self.verdict.setText("Running: the figures before and after appear when the run ends."
                                 if self.job is not None else
                                 "Run the optimiser to compare the design before and after.")
            self.verdict.setStyleSheet("")
            self.apply_button.setEnabled(False)
            self.apply_button.setText("Apply to the cam")
            return
        figs = opt.figures(res)
        self._fill(self.figure_table, [f.cells() for f in figs])
        for r, f in enumerate(figs):
            for col, v in ((1, f.before), (2, f.after)):
                if f.name in ("design checks", "worst constraint") and isinstance(v, str):
                    bad = v.startswith("FAIL") or v.endswith("FAILS")
                    self.figure_table.item(r, col).setForeground(QtGui.QBrush(QtGui.QColor(_RED if bad else _GREEN)))
        colours = {"pass": _GREEN, "fail": _RED, "skipped": _AMBER}
        checks = opt.check_comparison(res)
        self.check_table.setRowCount(len(checks))
        for r, c in enumerate(checks):
            cells = c.cells()   # check, limit, before, at, status, after, at, status
            items = [cells[0], cells[1], f"{cells[2]} at {cells[3]} — {cells[4]}",
                     f"{cells[5]} at {cells[6]} — {cells[7]}"]
            for col, text in enumerate(items):
                item = QtGui.QTableWidgetItem(text)
                status = cells[4] if col == 2 else cells[7] if col == 3 else None
                if status in colours:
                    item.setForeground(QtGui.QBrush(QtGui.QColor(colours[status])))
                if col == 0:
                    item.setToolTip(c.after.description)
                self.check_table.setItem(r, col, item)
        self._fit(self.figure_table, 1)
        self._fit(self.check_table, 2)
        if res.feasible:
            self.verdict.setText(f"{res.status_text} (the dense re-check). "
                                 "Apply writes the optimised design and these settings into the cam "
                                 "(one undo step).")
            self.verdict.setStyleSheet(f"color: {_GREEN}")
            self.apply_button.setText("Apply to the cam")
        else:
            self.verdict.setText(f"{res.status_text} (the dense re-check). "
                                 "Apply only if you accept that; you will be asked to confirm.")
            self.verdict.setStyleSheet(f"color: {_RED}; font-weight: bold")
            self.apply_button.setText("Apply anyway…")
        self.apply_button.setEnabled(True)

    @staticmethod
    def scroll_to(widget: Any) -> None:
        """Scroll the task view so that ``widget`` (a box of the panel) starts at its top."""
        area = widget.parentWidget()
        while area is not None and not isinstance(area, QtGui.QScrollArea):
            area = area.parentWidget()
        if area is None or area.widget() is None:
            return
        y = widget.mapTo(area.widget(), QtCore.QPoint(0, 0)).y()
        area.verticalScrollBar().setValue(max(0, y - 30))

    @staticmethod
    def _fit(table: Any, fixed: int) -> None:
        """The first ``fixed`` columns to their contents, the others share the width (text wraps);
        the table as high as its rows, so the task view scrolls, not the table."""
        header = table.horizontalHeader()
        for c in range(table.columnCount()):
            header.setSectionResizeMode(c, QtGui.QHeaderView.ResizeToContents if c < fixed
                                        else QtGui.QHeaderView.Stretch)
        table.setWordWrap(True)
        table.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarAlwaysOff)
        table.setVerticalScrollBarPolicy(QtCore.Qt.ScrollBarAlwaysOff)
        table.resizeRowsToContents()
        rows = sum(table.rowHeight(r) for r in range(table.rowCount()))
        table.setFixedHeight(header.sizeHint().height() + rows + 2 * table.frameWidth() + 6)

    @staticmethod
    def _fill(table: Any, rows: list[list[str]]) -> None:
        table.setRowCount(len(rows))
        for r, row in enumerate(rows):
            for c, text in enumerate(row):
                table.setItem(r, c, QtGui.QTableWidgetItem(text))

    def _draw_plot(self, history: list[tuple[int, float, float, str]]) -> None:
        """Redraw the convergence plot: one line per phase (their data replaced, not the axes
        rebuilt, so a redraw costs the GUI thread little while the worker runs)."""
        if getattr(self, "fig", None) is None:
            return

        ax, av = self.ax_obj, self.ax_viol
        data = opt.history_arrays(history)
        objective = self.job.spec.optimise.objective if self.job else self.objective.currentData()
        if set(data) != set(self._lines) or not data:
            for line in [ln for pair in self._lines.values() for ln in pair]:
                line.remove()
            self._lines = {}
            for k, phase in enumerate(data):
                colour = f"C{k % 10}"
                lo, = ax.plot([], [], ".-", ms=2, lw=0.8, color=colour,
                              label=f"{phase or 'run'} [{self._phase_unit(phase, objective)}]")
                lv, = av.plot([], [], ".", ms=2, color=colour)
                self._lines[phase] = (lo, lv)
            legend = ax.get_legend()
            if legend is not None:
                legend.remove()
            if data:
                ax.legend(fontsize=6, loc="upper right")
            ax.set_ylabel(self._unit(objective), fontsize=7)
        for phase, (it, f, v) in data.items():
            lo, lv = self._lines[phase]
            lo.set_data(it, f)
            lv.set_data(it, np.maximum(v, 1e-9))
        for a in (ax, av):
            a.relim()
            a.autoscale_view()
        if getattr(self, "canvas", None) is not None:
            t0 = time.perf_counter()
            self.canvas.draw()
            self.plot_seconds.append(time.perf_counter() - t0)

    # -- apply / close
    def apply(self) -> bool:
        """Write the result into the cam (one undo step); ask first if it fails a check."""
        res = self.result
        if res is None or self.running:
            return False
        allow = res.feasible
        if not allow:
            answer = QtGui.QMessageBox.question(
                FreeCADGui.getMainWindow(), "Apply a failing design?",
                f"The optimised design fails the dense re-check ({', '.join(res.checks.failed)}).\n"
                "Apply it to the cam anyway?", QtGui.QMessageBox.Yes | QtGui.QMessageBox.No,
                QtGui.QMessageBox.No)
            if answer != QtGui.QMessageBox.Yes:
                self._say("Not applied.", _AMBER)
                return False
        try:
            opt.apply_result(self.obj, res, allow_failing=True)
        except opt.ApplyError as exc:
            self._say(str(exc), _RED)
            FreeCAD.Console.PrintError(f"{self.obj.Label}: optimise: {exc}\n")
            return False
        self.applied = True
        FreeCAD.Console.PrintMessage(f"{self.obj.Label}: optimised design applied ({res.objective} "
                                     f"{res.initial_value:.6g} → {res.value:.6g}); Undo restores the cam\n")
        QtCore.QTimer.singleShot(0, self._close)   # not from inside the button's own signal
        return True

    def getStandardButtons(self) -> int:
        return standard_buttons("Close")

    def reject(self) -> bool:
        """Close: nothing is written; a run in progress is cancelled."""
        if self.running:
            self.job.cancel()
        self._timer.stop()
        self._close()
        return True

    def _abandon(self) -> None:
        """The panel's widgets are gone: cancel a run in progress (touches no widget)."""
        if self.job is not None and self.job.running:
            self.job.cancel()
        if self in _PANELS:
            _PANELS.remove(self)

    def _close(self) -> None:
        self._timer.stop()
        if self in _PANELS:
            _PANELS.remove(self)
        FreeCADGui.Control.closeDialog()


def open_panel(obj: Any) -> OptimiserPanel | None:
    """Show the optimiser panel for ``obj`` (closing another task panel first)."""
    if FreeCADGui.Control.activeDialog():
        FreeCADGui.Control.closeDialog()
    try:
        panel = OptimiserPanel(obj)
    except SpecError as exc:
        FreeCAD.Console.PrintError(f"{obj.Label}: cannot optimise: {props.describe_field(exc.field)}: {exc.rule}\n")
        return None
    _PANELS[:] = [panel]
    FreeCADGui.Control.showDialog(panel)
    return panel


def active_panel() -> OptimiserPanel | None:
    """The open optimiser panel (tests and scripts)."""
    return _PANELS[-1] if _PANELS else None
