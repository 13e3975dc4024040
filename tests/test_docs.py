"""The README documents every command-line option and every scenario field, with defaults and
units: its tables are generated from the parser and the Scenario dataclass, and must be current."""

import re
from pathlib import Path

import pytest

from fivebar_drake.cli import EXIT_CODES, options_markdown
from fivebar_drake.simulation.scenario import Scenario, fields_markdown

README = (Path(__file__).parent.parent / "README.md").read_text()


@pytest.mark.parametrize("name, generate", [("options-table", options_markdown),
                                            ("scenario-table", fields_markdown)])
def test_readme_tables_are_current(name, generate):
    block = re.search(rf"<!-- {name}:[^>]*-->\n(.*?)\n<!-- /{name} -->", README, re.S)
    assert block, f"README lacks the {name} block"
    assert block.group(1) == generate(), f"README {name} is stale; replace it with:\n{generate()}"


def test_every_field_and_code_is_documented():
    import dataclasses

    for f in dataclasses.fields(Scenario):
        assert f"| `{f.name}` |" in README and f.metadata["doc"]
    for code in re.findall(r"^  (\d+) ", EXIT_CODES, re.M):
        assert re.search(rf"^\| ({code}|\d+, {code}|{code}, \d+) \|", README, re.M), code


def test_readme_sweep_example_is_the_packaged_file():
    block = re.search(r"<!-- sweep-example:[^>]*-->\n```yaml\n(.*?)```\n<!-- /sweep-example -->",
                      README, re.S)
    assert block, "README lacks the sweep-example block"
    path = Path(__file__).parent.parent / "fivebar_drake" / "data" / "sweep_example.yaml"
    assert block.group(1) == path.read_text()
