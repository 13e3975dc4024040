"""The entry page of an output folder: index.md and index.html (one static page, no server).

It computes nothing: it reads what the other commands wrote. The answer is the envelope's
design answer (envelope/report.design_answer, in envelope.json: the design's envelope,
DIR/envelope, else the co-design's simulated default design); the fix is the co-design's
recommended design (design.json's answer, with its spec sheet's tables); the maneuver table is
the envelope's; the pictures are those of PICTURES that exist; and every report (*.md) and
recording (*.rrd) under DIR is linked, the static analyses labelled as the seed's estimate.
"""

from __future__ import annotations

import html
import json
from pathlib import Path

import markdown

from fivebar_drake.codesign.dossier import DOSSIER_DIR, SHEET_FILE
from fivebar_drake.core.files import write_atomic
from fivebar_drake.core.text import figure, verdict_word
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.envelope.report import worst_sf

INDEX_FILES = ("index.md", "index.html")
ENVELOPES = ("envelope/envelope.json", "codesign/finalists/default/envelope.json")
DESIGN = "codesign/design.json"
# the pictures shown inline where they exist: (path under DIR, caption)
PICTURES = (
    ("envelope/operating_points.png", "Each maneuver's motor operating points against the "
                                      "torque–speed envelope"),
    ("envelope/duty_cycle.png", "The duty cycle's winding temperatures"),
    ("codesign/pareto.png", "The co-design's candidates, the recommended design labelled"),
    ("optimal/optimal_jump.png", "The highest jump for any controller"),
    ("simulation/trot/sim_torques.png", "The default trot's motor torques"),
    ("gear_comparison.png", "The default trot against the 11.5:1 gear"),
    ("gait_comparison.png", "The default trot against the walk"),
)
STATIC = "the seed's static estimate (a model, not a verdict on the robot)"
STYLE = """body{font:16px/1.5 system-ui,sans-serif;max-width:60rem;margin:2rem auto;padding:0 1rem;
color:#222}h1{font-size:1.6rem}h2{margin-top:2rem;border-bottom:1px solid #ddd}
table{border-collapse:collapse;margin:1rem 0;font-size:.9rem}td,th{border:1px solid #ccc;
padding:.25rem .5rem;text-align:left}th{background:#f4f4f4}img{max-width:100%;
border:1px solid #eee}.answer{font-size:1.2rem;padding:.75rem 1rem;background:#f6f8fa;
border-left:4px solid #555}code{background:#f4f4f4;padding:0 .2rem}"""


def _read(path: Path, needs: str) -> dict | None:
    """A JSON output, None where it is missing; ParameterError naming one that is broken or
    lacks the key needs (written by an older version: the command is to be run again)."""
    if not path.is_file():
        return None
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as err:
        raise ParameterError(f"cannot be read as an output of fivebar-drake ({err})",
                             source=str(path)) from None
    if not isinstance(data, dict) or needs not in data:
        raise ParameterError(f"has no {needs!r}: written by another version of fivebar-drake "
                             "or not by it; run its command again", source=str(path))
    return data


def _title(path: Path) -> str:
    """A report's title: its first heading, else its first line, shortened."""
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.strip():
            text = line.lstrip("# ").strip()
            return text if len(text) <= 90 else text[:87] + "..."
    return path.name


def _plain(text: str) -> str:
    """Text from an output made safe in the page: HTML escaped, a table's bar escaped."""
    return html.escape(str(text), quote=False).replace("|", "\\|")


def _maneuver_rows(envelope: dict, where: str) -> list[str]:
    """The maneuver table: this controller's verdict and worst safety factor, the need for any
    controller and the motors' safety factor on it, whom a failure blames, report, recording."""
    rows = ["| maneuver | this controller | deciding check | worst SF | any controller needs "
            "(N·m) | SF on it | whom a failure blames | report | recording |",
            "|---|---|---|---|---|---|---|---|---|"]
    for name, e in envelope["maneuvers"].items():
        need = e.get("any_controller") or {}
        folder = f"{where}/{e['folder']}"
        name = _plain(name)
        rows.append(
            f"| {name} | {verdict_word(e['verdict'])} | {e.get('deciding_check') or '—'} | "
            f"{figure(worst_sf(e))} | {figure(need.get('floor_Nm'))} | "
            f"{figure(need.get('floor_safety_factor'))} | {need.get('fails_for') or '—'} | "
            f"[summary]({folder}/summary.md) | [run.rrd]({folder}/run.rrd) |")
    return rows


def _sheet_tables(path: Path) -> list[str]:
    """The spec sheet's sections and tables (its title and answer are the page's)."""
    lines = path.read_text(encoding="utf-8").splitlines()
    return [line.replace("## ", "### ", 1) if line.startswith("## ") else line
            for line in lines if line.startswith(("## ", "|")) or not line.strip()]


def _links(root: Path) -> list[str]:
    """Every report and recording under root, by folder."""
    lines, folder = [], None
    files = sorted(p for p in root.rglob("*") if p.suffix in (".md", ".rrd")
                   and p.relative_to(root).as_posix() not in INDEX_FILES)
    for path in files:
        rel = path.relative_to(root)
        top = rel.parts[0] if len(rel.parts) > 1 else "."
        if top != folder:
            folder = top
            lines += ["", f"**{folder}/**" if folder != "." else "**this folder**", ""]
        if path.suffix == ".rrd":
            text = f"recording (open with `rerun {rel.as_posix()}`)"
        else:
            text = _plain(_title(path))
            if rel.name == "report.md" and (rel.parts[0] in ("analysis", "robots")):
                text += f": {STATIC}"
        lines.append(f"- [{rel.as_posix()}]({rel.as_posix()}): {text}")
    return lines


def index_markdown(root: Path) -> str:
    """index.md of the output folder root (module docstring); ParameterError where root holds
    neither an envelope nor a co-design."""
    found = [(where, _read(root / where, "design_answer")) for where in ENVELOPES]
    envelope_at, envelope = next(((w, e) for w, e in found if e is not None), (None, None))
    design = _read(root / DESIGN, "why")
    if envelope is None and design is None:
        raise ParameterError(f"holds no envelope ({' or '.join(ENVELOPES)}) and no co-design "
                             f"({DESIGN}): run `fivebar-drake envelope` or `codesign` into it "
                             "first", source=str(root))
    lines = ["# The answer for this design", ""]
    if envelope is not None:
        answer = envelope["design_answer"]
        lines += [f'<p class="answer">{html.escape(answer["text"])}</p>', "",
                  f"From the envelope in `{Path(envelope_at).parent.as_posix()}/` "
                  f"({_plain(envelope['spec'])}). This controller's worst: "
                  f"{verdict_word(envelope['verdict'])}.", ""]
    if design is not None:
        lines += [f"**Fix:** {_plain(design['answer'])}", ""]
        lines += [f"- {_plain(item)}" for item in design["why"]] + [""]
    if envelope is not None:
        where = Path(envelope_at).parent.as_posix()
        lines += ["## Maneuvers", "", envelope["thresholds"], ""]
        lines += _maneuver_rows(envelope, where) + [""]
    sheet = root / "codesign" / DOSSIER_DIR / SHEET_FILE
    if sheet.is_file():
        folder = f"codesign/{DOSSIER_DIR}"
        lines += ["## Spec sheet of the recommended design", "",
                  f"[{SHEET_FILE}]({folder}/{SHEET_FILE}); its models: "
                  f"[quadruped.sdf]({folder}/quadruped.sdf) (Drake), "
                  f"[quadruped.xml]({folder}/quadruped.xml) (MuJoCo), "
                  f"[design.toml](codesign/design.toml) (the parameter file).", ""]
        lines += _sheet_tables(sheet) + [""]
    pictures = [(p, c) for p, c in PICTURES if (root / p).is_file()]
    if pictures:
        lines += ["## Pictures", ""]
        for path, caption in pictures:
            lines += [f"**{caption}** ([{path}]({path}))", "", f"![{caption}]({path})", ""]
    lines += ["## Every report and recording"] + _links(root) + [""]
    return "\n".join(lines)


def index_html(text: str) -> str:
    """index.md as one static HTML page (its tables, links and pictures; no script)."""
    body = markdown.markdown(text, extensions=["tables"])
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<title>fivebar_drake: the answer for this design</title>"
            f"<style>{STYLE}</style></head><body>\n{body}\n</body></html>\n")


def write_index(root: str | Path) -> list[Path]:
    """Write index.md and index.html into the output folder root, each atomically."""
    root = Path(root)
    if not root.is_dir():
        raise ParameterError("is not a folder of fivebar-drake outputs", source=str(root))
    text = index_markdown(root)
    return [write_atomic(root / INDEX_FILES[0], text),
            write_atomic(root / INDEX_FILES[1], index_html(text))]
