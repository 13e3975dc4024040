"""The output style guide (docs/output_style.md) as checks over written reports: each function
returns the breaches it finds as "file:line: rule: text" strings (empty: the file keeps the rule).
The glossary is read from the guide itself, so a term a table uses is defined there or is
reported here."""

from __future__ import annotations

import re
from functools import lru_cache
from pathlib import Path

GUIDE = Path(__file__).resolve().parents[1] / "docs" / "output_style.md"

# rule 1: the answer names a verdict (or, for a design search or a seed check, its outcome)
ANSWER_WORDS = re.compile(r"\b(PASS|WARN|FAIL|INSUFFICIENT|NOT ACHIEVED|No verdict|"
                          r"No design recommended|Recommended|reproduce[sd]?|allow)\b")
ANSWER_CHARS = 200     # the answer's line at most (fivebar_drake.core.text.ANSWER_CHARS)
PARAGRAPH_WORDS = 80   # a paragraph of prose at most; longer: a list or a table
# ... and a figure: a number with its unit, a safety factor or a count
FIGURE = re.compile(r"\bSF \d|\d+ of \d+|"
                    r"\d(?:\.\d+)? ?(?:N·m|N\b|%|°C|m/s|mm|m\b|rad/s|A\b|kg|W\b|deg\b|s\b)")
# rule 2: spellings the guide forbids, with the unit they mean
WRONG_UNITS = {
    "N m": re.compile(r"(?<![\w.])N m\b"), "N*m": re.compile(r"N\*m"),
    "Nm": re.compile(r"(?<![\w_])Nm\b"), "N.m": re.compile(r"\bN\.m\b"),
    "C for °C": re.compile(r"\d C\b|\(C\)|\bdeg ?C\b|℃"),
    "° for an angle": re.compile(r"°(?!C)"),
    "degrees": re.compile(r"\bdegrees\b"), "rad/s²": re.compile(r"rad/s²|rad/s/s"),
    "m²": re.compile(r"m²"), "sec": re.compile(r"\d ?secs?\b"), "um": re.compile(r"\d ?um\b"),
    "×": re.compile(r"\d ?×"),
    "NOT_ACHIEVED for NOT ACHIEVED": re.compile(r"\bNOT_ACHIEVED\b"),
}
# rule 3
NOT_A_NUMBER = re.compile(r"(?<![\w`])(nan|NaN|inf|-inf)(?![\w`])")
NEGATIVE_ZERO = re.compile(r"(?<![\w.])[-−]0(?:\.0+)?(?![\d.])")
UNROUNDED = re.compile(r"(?<![\w.])(?:0\.0*[1-9]\d{4,}|[1-9]\d*\.\d{5,})(?!\w)")  # 0.02432 is 4
# rule 5: a torque verdict carries its thresholds
TORQUE_VERDICT = re.compile(r"\b(PASS|WARN|FAIL)\b")
THRESHOLDS = re.compile(r"SF ≥ 2")
SEPARATOR = re.compile(r"^\|[-:| ]+\|\s*$")


@lru_cache(maxsize=1)
def glossary() -> frozenset[str]:
    """The glossary's terms (fivebar_drake/core/glossary.py: each row's terms, split at commas
    and slashes) and its words in their everyday sense, lower case."""
    from fivebar_drake.core.glossary import EVERYDAY, TERMS

    terms = {t.strip().lower() for names, _ in TERMS for t in re.split(r"[,/]", names)}
    terms.update(w.strip().lower() for w in EVERYDAY)
    return frozenset(t for t in terms if t)


def header_words(cell: str) -> list[str]:
    """The words of a table header cell that must be glossary terms: units in parentheses,
    numbers, code spans, parameter paths and names with digits are left out."""
    cell = re.sub(r"\([^)]*\)|`[^`]*`|\S*=\S*|°C", " ", cell)
    words = re.findall(r"[A-Za-z][\w'.^-]*", cell)
    return [w.rstrip(".") for w in words
            if not re.search(r"\d|\w\.\w", w) and len(w) > 1   # one letter: a symbol
            and w not in ("mm", "ms", "kg", "Hz")]


def _known(words: list[str], terms: frozenset[str]) -> list[str]:
    """The words not covered by a glossary term: the longest terms made of consecutive words
    first, then single words (a possessive 's and a plural s taken off)."""
    lower = [w.lower() for w in words]
    covered = [False] * len(lower)
    for n in range(len(lower), 0, -1):
        for i in range(len(lower) - n + 1):
            if not any(covered[i:i + n]) and " ".join(lower[i:i + n]) in terms:
                covered[i:i + n] = [True] * n
    unknown = []
    for w, c in zip(lower, covered):
        if c:
            continue
        stems = {w, re.sub(r"'s$", "", w), re.sub(r"s$", "", w)}
        if not stems & terms:
            unknown.append(w)
    return unknown


def violations(path: Path) -> list[str]:
    """Every breach of the guide's rules in the report at path."""
    text = path.read_text(encoding="utf-8")
    lines = text.splitlines()
    found = []

    def breach(k, rule, line):
        found.append(f"{path}:{k + 1}: {rule}: {line.strip()[:160]}")

    body = [(k, line) for k, line in enumerate(lines) if line.strip()]
    if body and body[0][1].startswith("# "):
        body = body[1:]
    if not body:
        breach(0, "empty report", "")
    else:
        k, first = body[0]
        if not ANSWER_WORDS.search(first) or not FIGURE.search(first):
            breach(k, "the first line is not the answer (a verdict and a figure)", first)
        if len(first) > ANSWER_CHARS:
            breach(k, f"the first line is longer than {ANSWER_CHARS} characters", first)
    for k, words in paragraphs(lines):
        if words > PARAGRAPH_WORDS:
            breach(k, f"a paragraph of {words} words, more than {PARAGRAPH_WORDS} (a list or a "
                      "table instead)", lines[k])
    if TORQUE_VERDICT.search(text) and "SF" in text and not THRESHOLDS.search(text):
        breach(0, "a verdict without its thresholds (SF ≥ 2 pass, ≥ 1.5 warn)", "")
    terms = glossary()
    for k, line in enumerate(lines):
        bare = re.sub(r"`[^`]*`", "", line)
        for unit, pattern in WRONG_UNITS.items():
            if pattern.search(bare):
                breach(k, f"unit spelled {unit}", line)
        if NOT_A_NUMBER.search(bare):
            breach(k, "nan or inf", line)
        if NEGATIVE_ZERO.search(bare):
            breach(k, "negative zero", line)
        if UNROUNDED.search(bare):
            breach(k, "more than 4 decimals", line)
        if line.startswith("|") and k + 1 < len(lines) and SEPARATOR.match(lines[k + 1]):
            for cell in line.strip().strip("|").split("|"):
                unknown = _known(header_words(cell), terms)
                if unknown:
                    breach(k, f"header term not in the glossary: {' '.join(unknown)}",
                           cell)
    return found


def paragraphs(lines: list[str]) -> list[tuple[int, int]]:
    """(first line's index, words) of each paragraph of prose: consecutive lines that are not
    blank, a heading, a table row or in a code block; each list item is its own paragraph."""
    out, start, words, code = [], None, 0, False
    for k, line in enumerate(lines + [""]):
        if line.startswith("```"):
            code = not code
        item = line.lstrip().startswith(("- ", "* ")) or re.match(r"\s*\d+\. ", line)
        prose = line.strip() and not code and not line.startswith(("#", "|", "```"))
        if start is not None and (not prose or item):
            out.append((start, words))
            start = None
        if prose:
            if start is None:
                start, words = k, 0
            words += len(line.split())
    return out


def report_violations(root: Path) -> list[str]:
    """The breaches of every report (*.md) under root (or root itself, a file)."""
    files = [root] if root.is_file() else sorted(root.rglob("*.md"))
    return [v for f in files for v in violations(f)]
