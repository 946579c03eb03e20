"""The mechanism in motion as files (issue 24 item 5; docs/animation.md): an animated GIF (matplotlib's
PillowWriter; Pillow comes with matplotlib) or an MP4 (FFMpegWriter, when ``ffmpeg`` is on the
PATH), and a still PNG of one frame — all drawn from
:class:`~cam_workbench.generators.machine.frames.MachineFrames` (plain data; nothing is computed
here).

Every frame has the same axes (the frames' ``bounds``) and the picture has a fixed size in pixels:
``width_px`` wide, the height following the bounds' aspect ratio (even numbers, as H.264 wants),
so the output's size depends on the frames alone.  The artists are made once and moved frame by
frame (no redraw of the figure's furniture), and a GIF's frames share one palette (the first
frame's, adaptive, :data:`GIF_COLORS` colours): small files, no colour flicker.
"""
from __future__ import annotations

import io
import os
import shutil
import tempfile
from pathlib import Path
from typing import Any, Callable

import numpy as np

from cam_workbench.generators.errors import MissingDependency, SpecError
from cam_workbench.generators.machine.frames import CamFrames, MachineFrames

from .atomic import write_bytes_atomic
from .plots import BLACK, COLORS, MATERIAL, ROLLER_FILL

#: progress callback: (done, total, what) — the project's convention (cam_workbench.machine)
Progress = Callable[[int, int, str], None]
#: the formats write_animation writes, by file suffix
FORMATS = ("gif", "mp4")
#: frames per second unless told
DEFAULT_FPS = 12
#: picture width [px] unless told
DEFAULT_WIDTH = 800
#: colours of a GIF's shared palette
GIF_COLORS = 64
DPI = 100
#: (width, height) fractions of the picture the plot takes (the rest: the title band and margins)
PLOT_FRACTION = (0.96, 0.86)
LINK_COLOR = "#2e7d32"
TOOL_COLOR = "#6a1b9a"
TOOL_FILL = "#d7c4e6"


def _mpl() -> tuple[Any, Any, Any, Any]:
    """matplotlib's Figure, its Agg canvas, patches and animation modules."""
    from matplotlib import animation, patches  # deferred: matplotlib, loaded when an animation is drawn
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # deferred: matplotlib, as above
    from matplotlib.figure import Figure  # deferred: matplotlib, as above

    return Figure, FigureCanvasAgg, patches, animation


def picture_size(frames: MachineFrames, width_px: int = DEFAULT_WIDTH) -> tuple[int, int]:
    """(width, height) [px] of the pictures: ``width_px`` and the bounds' aspect ratio plus the
    title band, both even, the height between 160 and 2 × width."""
    x0, y0, x1, y1 = frames.bounds
    w = int(width_px) // 2 * 2
    if w < 160:
        raise SpecError("width_px", f"is {width_px!r}, must be at least 160 pixels")
    h = w * (y1 - y0) / max(x1 - x0, 1e-300) * PLOT_FRACTION[0] / PLOT_FRACTION[1]
    h = int(round(min(max(h, 160.0), 2.0 * w) / 2.0)) * 2
    return w, h


class _Scene:
    """The figure and its artists, made once; :meth:`show` moves them to frame i."""

    def __init__(self, frames: MachineFrames, width_px: int) -> None:
        Figure, Canvas, patches, _ = _mpl()
        self.frames = frames
        self.size = picture_size(frames, width_px)
        w, h = self.size
        self.fig = Figure(figsize=(w / DPI, h / DPI), dpi=DPI)
        Canvas(self.fig)
        fw, fh = PLOT_FRACTION
        ax = self.fig.add_axes((0.5 * (1 - fw), 0.02, fw, fh))
        x0, y0, x1, y1 = frames.bounds
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal", adjustable="box")
        ax.set_axis_off()
        self.ax = ax
        self.title = self.fig.text(0.5, 0.975, "", ha="center", va="top", fontsize=11)
        scale = frames.bounds[2] - frames.bounds[0]
        self.cams = [self._cam_artists(c, patches, scale) for c in frames.cams]

    def _cam_artists(self, c: CamFrames, patches: Any, scale: float) -> dict[str, Any]:
        ax = self.ax
        a: dict[str, Any] = {}
        a["cam"] = ax.add_patch(patches.Polygon(c.outline[0], closed=True, facecolor=MATERIAL,
                                                edgecolor=COLORS["profile"], linewidth=1.2, zorder=1))
        if c.bore_radius > 0:
            ax.add_patch(patches.Circle(tuple(c.centre), c.bore_radius, facecolor="white",
                                        edgecolor=COLORS["profile"], linewidth=0.8, zorder=2))
        a["mark"], = ax.plot(*c.mark[0].T, color=COLORS["profile"], linewidth=1.4, zorder=3)
        ax.plot([c.centre[0]], [c.centre[1]], marker="+", color=BLACK, markersize=8, zorder=3)
        ax.text(c.centre[0], float(c.outline[..., 1].min()) - 0.01 * scale, c.name, ha="center", va="top",
                fontsize=9, zorder=6, clip_on=False)
        if c.tool_outline is not None:
            a["tool"] = ax.add_patch(patches.Polygon(c.tool_outline[0], closed=True, facecolor=TOOL_FILL,
                                                     edgecolor=TOOL_COLOR, linewidth=1.0, alpha=0.75, zorder=8))
        a["links"] = [ax.plot(*self._link(c, pair, 0).T, color=LINK_COLOR, linewidth=2.2, solid_capstyle="round",
                              zorder=4)[0] for pair in c.links]
        a["joints"] = None
        if c.joints:
            pts = np.array([j[0] for j in c.joints.values()])
            a["joints"], = ax.plot(pts[:, 0], pts[:, 1], linestyle="none", marker="o", markersize=4,
                                   markerfacecolor="white", markeredgecolor=LINK_COLOR, zorder=5)
        a["segments"] = [ax.plot(*c.segments[0, k].T, color=COLORS["follower"],
                                 linewidth=3.0 if role == "face" else 2.4, solid_capstyle="butt", zorder=5)[0]
                         for k, role in enumerate(c.roles)]
        a["roller"] = None
        if c.roller_radius > 0:
            a["roller"] = ax.add_patch(patches.Circle(tuple(c.point[0]), c.roller_radius, facecolor=ROLLER_FILL,
                                                      edgecolor=COLORS["follower"], linewidth=1.0, zorder=6))
        a["point"], = ax.plot(*c.point[0], marker="o", markersize=2.5, color=COLORS["pitch"], zorder=7)
        a["pivot"] = None
        if c.pivot is not None:
            a["pivot"], = ax.plot(*c.pivot[0], marker="o", markersize=5, markerfacecolor="white",
                                  markeredgecolor=COLORS["follower"], markeredgewidth=1.4, zorder=7)
        return a

    @staticmethod
    def _link(c: CamFrames, pair: tuple[str, str], i: int) -> np.ndarray:
        return np.array([c.joints[pair[0]][i], c.joints[pair[1]][i]])

    def show(self, i: int) -> None:
        """Move every artist to frame ``i``."""
        f = self.frames
        for c, a in zip(f.cams, self.cams):
            a["cam"].set_xy(c.outline[i])
            a["mark"].set_data(*c.mark[i].T)
            if "tool" in a:
                a["tool"].set_xy(c.tool_outline[i])
            for line, pair in zip(a["links"], c.links):
                line.set_data(*self._link(c, pair, i).T)
            if a["joints"] is not None:
                pts = np.array([j[i] for j in c.joints.values()])
                a["joints"].set_data(pts[:, 0], pts[:, 1])
            for k, line in enumerate(a["segments"]):
                line.set_data(*c.segments[i, k].T)
            if a["roller"] is not None:
                a["roller"].set_center(tuple(c.point[i]))
            a["point"].set_data([c.point[i, 0]], [c.point[i, 1]])
            if a["pivot"] is not None:
                a["pivot"].set_data([c.pivot[i, 0]], [c.pivot[i, 1]])
        self.title.set_text(f"{f.name} — machine angle φ = {f.machine_angle[i]:.1f}°")

    def rgba(self) -> np.ndarray:
        """The drawn picture (h, w, 4) uint8."""
        canvas = self.fig.canvas
        canvas.draw()
        return np.asarray(canvas.buffer_rgba()).copy()


def _check_index(frames: MachineFrames, i: int) -> int:
    n = len(frames)
    if not isinstance(i, (int, np.integer)) or not -n <= int(i) < n:
        raise SpecError("frame", f"is {i!r}, must be a frame index from 0 to {n - 1}")
    return int(i) % n


def frame_png_bytes(frames: MachineFrames, i: int, *, width_px: int = DEFAULT_WIDTH) -> bytes:
    """Frame ``i`` as PNG bytes (``picture_size`` pixels; no timestamps: the same frames give the
    same bytes)."""
    i = _check_index(frames, i)
    scene = _Scene(frames, width_px)
    scene.show(i)
    buf = io.BytesIO()
    scene.fig.savefig(buf, format="png", dpi=DPI, metadata={"Software": None})
    return buf.getvalue()


def write_frame(frames: MachineFrames, i: int, path: str | os.PathLike[str], *,
                width_px: int = DEFAULT_WIDTH) -> Path:
    """Write frame ``i`` as a PNG still (the README's picture), atomically."""
    return write_bytes_atomic(path, frame_png_bytes(frames, i, width_px=width_px))


def require_matplotlib(option: str = "--animation gif") -> None:
    """Check that the animation can be drawn: matplotlib and Pillow (which matplotlib brings, and
    which writes the GIF) import.

    Raises:
        MissingDependency: either is missing or fails to import (naming ``option`` and
            ``--animation none``).
    """
    try:
        _mpl()
    except ImportError as exc:
        raise MissingDependency(f"animations ({option}) need matplotlib and Pillow, cam-workbench's own "
                                "dependencies (pip install --force-reinstall cam-workbench); --animation none "
                                f"writes everything else ({exc})") from exc


def require_ffmpeg(option: str = "--animation mp4") -> str:
    """The ffmpeg executable's path.

    Raises:
        MissingDependency: ffmpeg is not on the PATH (naming ``option`` and the GIF alternative).
    """
    exe = shutil.which("ffmpeg")
    if exe is None:
        raise MissingDependency(f"MP4 animations ({option}) need the ffmpeg program on the PATH (Debian: apt install "
                                "ffmpeg); a GIF (--animation gif) needs only matplotlib and Pillow")
    return exe


class _SharedPaletteWriter:
    """matplotlib's PillowWriter with every frame quantised to the first frame's palette."""

    @staticmethod
    def make(animation: Any, fps: int) -> Any:
        class Writer(animation.PillowWriter):  # type: ignore[misc, name-defined]
            def finish(self) -> None:
                first = self._frames[0].convert("RGB")
                pal = first.quantize(colors=GIF_COLORS, method=2, dither=0)   # 2: Pillow's fast octree
                frames = [pal] + [im.convert("RGB").quantize(palette=pal, dither=0) for im in self._frames[1:]]
                frames[0].save(self.outfile, save_all=True, append_images=frames[1:],
                               duration=int(round(1000 / self.fps)), loop=0, optimize=False)

        return Writer(fps=fps)


def animation_bytes(frames: MachineFrames, fmt: str = "gif", *, fps: int = DEFAULT_FPS,
                    width_px: int = DEFAULT_WIDTH, progress: Progress | None = None) -> bytes:
    """The animation of every frame, in order, looping, as ``fmt`` ("gif" or "mp4") bytes, at
    ``fps`` frames per second; ``progress(done, total, what)`` after each frame drawn.

    Raises:
        SpecError: an unknown format, fps not a whole number ≥ 1, or no frames.
        MissingDependency: "mp4" without ffmpeg on the PATH.
    """
    if fmt not in FORMATS:
        raise SpecError("--animation", f"is {fmt!r}, must be one of {', '.join(FORMATS)}")
    if isinstance(fps, bool) or not isinstance(fps, (int, np.integer)) or not 1 <= fps <= 100:
        raise SpecError("fps", f"is {fps!r}, must be a whole number of frames per second from 1 to 100")
    if len(frames) == 0:
        raise SpecError("frames", "has no frame to draw")
    if fmt == "mp4":
        require_ffmpeg()
    _, _, _, animation = _mpl()
    scene = _Scene(frames, width_px)
    if fmt == "gif":
        writer = _SharedPaletteWriter.make(animation, int(fps))
    else:
        writer = animation.FFMpegWriter(fps=int(fps), codec="libx264",
                                        extra_args=["-pix_fmt", "yuv420p", "-preset", "medium", "-crf", "23"],
                                        metadata={"title": frames.name})
    n = len(frames)
    with tempfile.TemporaryDirectory(prefix="cam-workbench-animation-") as tmp:
        out = Path(tmp) / f"animation.{fmt}"
        with writer.saving(scene.fig, str(out), DPI):
            for i in range(n):
                scene.show(i)
                writer.grab_frame()
                if progress:
                    progress(i + 1, n, f"frame {i + 1}/{n}")
        return out.read_bytes()


def write_animation(frames: MachineFrames, path: str | os.PathLike[str], *, fps: int = DEFAULT_FPS,
                    width_px: int = DEFAULT_WIDTH, progress: Progress | None = None) -> Path:
    """Write the animation to ``path`` atomically, the format from its suffix (.gif, .mp4); see
    :func:`animation_bytes`.

    Raises:
        SpecError: the suffix is neither .gif nor .mp4 (and :func:`animation_bytes`' errors).
        MissingDependency: .mp4 without ffmpeg on the PATH.
    """
    fmt = Path(path).suffix.lower().lstrip(".")
    if fmt not in FORMATS:
        raise SpecError("path", f"{os.fspath(path)!r}: the animation's file must end in .gif or .mp4")
    return write_bytes_atomic(path, animation_bytes(frames, fmt, fps=fps, width_px=width_px, progress=progress))


__all__ = ["DEFAULT_FPS", "DEFAULT_WIDTH", "FORMATS", "animation_bytes", "frame_png_bytes", "picture_size",
           "require_ffmpeg", "require_matplotlib", "write_animation", "write_frame"]
