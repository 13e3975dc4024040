"""The manual: the README is a front door (at most 300 lines, its links resolve); the
documentation site (docs/, mkdocs.yml) builds with warnings as errors; its reference pages are
generated from the code (tools/gen_docs.py) and current; every scenario field and exit code is
documented; the sweep page's example is the packaged file."""

import dataclasses
import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

from fivebar_drake.cli import EXIT_CODES
from fivebar_drake.simulation.scenario import Scenario

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text()
DOCS = ROOT / "docs"


def gen_docs():
    spec = importlib.util.spec_from_file_location("gen_docs", ROOT / "tools" / "gen_docs.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_readme_is_a_front_door():
    """At most 300 lines, the two commands, and every link to a file of the repository resolves."""
    assert len(README.splitlines()) <= 300
    assert "make demo" in README and "make test" in README
    for target in re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", README):
        if not target.startswith("http"):
            assert (ROOT / target).exists(), target


@pytest.mark.parametrize("name", ["options.md", "scenario.md", "summary.md", "specs.md",
                                  "glossary.md"])
def test_the_reference_pages_are_current(name):
    generated = gen_docs().pages()[name]
    assert (DOCS / "reference" / name).read_text() == generated, (
        f"docs/reference/{name} is stale: run tools/gen_docs.py")


def test_every_field_and_code_is_documented():
    scenario = (DOCS / "reference" / "scenario.md").read_text()
    for f in dataclasses.fields(Scenario):
        assert f"| `{f.name}` |" in scenario and f.metadata["doc"]
    for code in re.findall(r"^  (\d+) ", EXIT_CODES, re.M):
        assert re.search(rf"^\| ({code}|\d+, {code}|{code}, \d+) \|", README, re.M), code


def test_the_sweep_pages_example_is_the_packaged_file():
    page = (DOCS / "commands" / "sweep.md").read_text()
    block = re.search(r"<!-- sweep-example:[^>]*-->\n```yaml\n(.*?)```\n<!-- /sweep-example -->",
                      page, re.S)
    assert block, "docs/commands/sweep.md lacks the sweep-example block"
    path = ROOT / "fivebar_drake" / "data" / "sweep_example.yaml"
    assert block.group(1) == path.read_text()


def test_the_site_builds_with_warnings_as_errors(tmp_path):
    """mkdocs build --strict: a broken link, a page left out of the navigation or a missing
    anchor fails it."""
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir",
                           str(tmp_path / "site"), "--config-file", str(ROOT / "mkdocs.yml")],
                          capture_output=True, text=True, cwd=ROOT, timeout=300,
                          env={"NO_MKDOCS_2_WARNING": "1", "PATH": "/usr/bin:/bin"})
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "site" / "index.html").exists()
    assert (tmp_path / "site" / "reference" / "summary" / "index.html").exists()


def test_every_command_of_the_readme_runs_in_make_demo():
    """The README's tour is what `make demo` runs (CI runs it on every submission): each of its
    commands is a line of the Makefile's demo recipe ($(BIN) = .venv/bin, $(OUT) = out,
    $(DEMO_S) = 4.5)."""
    makefile = (ROOT / "Makefile").read_text()
    recipe = makefile.split("\ndemo:", 1)[1].split("\n\n", 1)[0].replace("\\\n", " ")
    recipe = re.sub(r"\s+", " ", recipe.replace("$(BIN)", ".venv/bin").replace("$(OUT)", "out")
                    .replace("$(DEMO_S)", "4.5"))
    commands = re.findall(r"^\.venv/bin/fivebar-drake .+$", README, re.M)
    assert len(commands) >= 4
    for command in commands:
        assert re.sub(r"\s+", " ", command.split("  #")[0].strip()) in recipe, command


def site_commands() -> list[tuple[str, str]]:
    """(page, command line) of every runnable command in the site's code blocks (not a usage
    synopsis with [OPTIONS] or ..., not a continued line)."""
    out = []
    for page in sorted(DOCS.rglob("*.md")):
        for lang, block in re.findall(r"^```(\w*)\n(.*?)^```", page.read_text(), re.S | re.M):
            if lang not in ("", "console", "bash", "sh"):
                continue
            for line in block.splitlines():
                line = line.split("  #")[0].strip()
                if (re.match(r"^(?:\.venv/bin/)?fivebar-drake .+$", line) and "[" not in line
                        and "..." not in line and not line.endswith("\\")):
                    out.append((page.name, line))
    return out


@pytest.mark.parametrize("page, command", site_commands())
def test_every_command_of_the_site_runs(page, command, tmp_path, monkeypatch):
    """Each runnable command the site gives runs as written (from the repository's root, its
    output folder moved to a temporary one) and exits 0."""
    import shlex

    from fivebar_drake.cli import main

    monkeypatch.chdir(ROOT)
    args = shlex.split(command.split("fivebar-drake", 1)[1])
    if args[0] != "--version":
        args += ["--out", str(tmp_path / "out")]
    try:
        assert main(args) == 0, f"{page}: {command}"
    except SystemExit as err:                          # --version exits 0
        assert err.code in (0, None), f"{page}: {command}"


def test_every_command_in_the_manual_parses():
    """Every command line the README and the site give in a code block (not a usage synopsis
    with [OPTIONS], not an output block) is a valid command: the command line's own parser takes
    it, and the files it names exist. The extension templates run in tests/test_extending.py;
    the demo's commands run in `make demo`."""
    import shlex

    from fivebar_drake.cli import parser

    pages = [ROOT / "README.md", *sorted(DOCS.rglob("*.md"))]
    checked = 0
    for page in pages:
        for lang, block in re.findall(r"^```(\w*)\n(.*?)^```", page.read_text(), re.S | re.M):
            if lang not in ("", "console", "bash", "sh"):
                continue
            for line in block.splitlines():
                line = line.split("  #")[0].strip()
                found = re.match(r"^(?:\.venv/bin/)?fivebar-drake (.+)$", line)
                if not found or "[" in line or "..." in line or line.endswith("\\"):
                    continue
                args = shlex.split(found.group(1))
                try:
                    parser().parse_args(args)
                except SystemExit as err:        # --version and --help exit 0
                    if err.code not in (0, None):
                        raise AssertionError(f"{page.name}: {line!r} does not parse") from err
                for arg in args:
                    if arg.startswith("fivebar_drake/"):
                        assert (ROOT / arg).exists(), f"{page.name}: {arg}"
                checked += 1
    assert checked >= 8


def test_the_style_guides_verdict_bands_are_the_packaged_checks():
    """docs/output_style.md's table of the verdict's bands gives the packaged [checks]."""
    from fivebar_drake.robots.quadruped.config import load_params

    c = load_params().checks
    text = (DOCS / "output_style.md").read_text().split("The verdict's bands")[1]
    table = text.split("\n\n")[1]
    rows = {line.split("|")[1].strip().split(":")[0]: line for line in table.splitlines()}
    assert f"≥ {c.sf_pass:g} | ≥ {c.sf_warn:g} | below {c.sf_warn:g}" in rows["torque"]
    assert (f"at most {c.speed_outside_fail * 100:g} %, margin ≥ {c.speed_margin_warn:g}"
            in rows["speed"])
    assert f"≥ {c.thermal_margin_warn:g} | ≥ 1 | below 1" in rows["thermal"]
    assert f"at most {c.achieved_max_limit_fraction * 100:g} %" in rows["achieved"]
