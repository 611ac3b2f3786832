"""Side-by-side renders of one instruction: every method's frame with the checker's verdicts
(``capframe grid``, the report's image grid)."""

from __future__ import annotations

import io
import textwrap
from pathlib import Path

from PIL import Image, ImageDraw

from ..errors import InputError
from ..scene._io import atomic_write, read_json

TILE_WIDTH = 320
MARGIN = 8
LINE = 14
OK, FAIL, NA = (30, 140, 60), (200, 40, 40), (120, 120, 120)


def _verdict_lines(report: dict) -> list[tuple[str, tuple[int, int, int]]]:
    """One coloured line per constraint row: ``region teddy bear: ok``."""
    lines = []
    for row in report["rows"]:
        state = row["satisfied"]
        word, colour = ("n/a", NA) if state is None else (("ok", OK) if state else ("FAIL", FAIL))
        lines.append((f"{row['constraint']}{' ' + row['subject'] if row['subject'] else ''}: {word}", colour))
    return lines


def _tile(method: str, render: Path, report: dict, rows: int) -> Image.Image:
    image = Image.open(render).convert("RGB")
    image = image.resize((TILE_WIDTH, round(image.height * TILE_WIDTH / image.width)))
    verdict = "all satisfied" if report["all_satisfied"] else f"{report['satisfied']}/{report['applicable']} satisfied"
    tile = Image.new("RGB", (TILE_WIDTH, image.height + (rows + 2) * LINE + MARGIN), "white")
    tile.paste(image, (0, 0))
    draw = ImageDraw.Draw(tile)
    y = image.height + 2
    draw.text((2, y), f"{method}: {verdict}", fill=OK if report["all_satisfied"] else FAIL)
    for text, colour in _verdict_lines(report):
        y += LINE
        draw.text((2, y), text, fill=colour)
    return tile


def grid_image(text: str, entries: list[tuple[str, Path, dict]]) -> Image.Image:
    """The instruction text above one tile per (method, render.png, check report)."""
    rows = max(len(report["rows"]) for _, _, report in entries)
    tiles = [_tile(method, render, report, rows) for method, render, report in entries]
    header = textwrap.wrap(text, width=(TILE_WIDTH * len(tiles)) // 7)
    width = TILE_WIDTH * len(tiles) + MARGIN * (len(tiles) + 1)
    top = MARGIN + LINE * len(header) + MARGIN
    out = Image.new("RGB", (width, top + max(t.height for t in tiles) + MARGIN), (235, 235, 235))
    draw = ImageDraw.Draw(out)
    for k, line in enumerate(header):
        draw.text((MARGIN, MARGIN + k * LINE), line, fill=(0, 0, 0))
    for k, tile in enumerate(tiles):
        out.paste(tile, (MARGIN + k * (TILE_WIDTH + MARGIN), top))
    return out


def grid_command(text: str, methods: list[str], results: list[str], checks: list[str], output: str) -> None:
    """``capframe grid``: ``methods``, ``results`` (result folders with ``render.png``) and
    ``checks`` (``capframe check -o`` reports) pair up in order."""
    if not (len(methods) == len(results) == len(checks)) or not methods:
        raise InputError(f"--methods ({len(methods)}), --results ({len(results)}) and --checks ({len(checks)}) must pair up")
    entries = []
    for method, folder, check in zip(methods, results, checks):
        render = Path(folder) / "render.png"
        if not render.is_file():
            raise InputError("has no render.png", source=str(folder))
        entries.append((method, render, read_json(check)))
    buffer = io.BytesIO()
    grid_image(text, entries).save(buffer, format="PNG")
    atomic_write(output, buffer.getvalue())
