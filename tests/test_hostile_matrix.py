"""Every subcommand of every mechanism under the same classes of hostile input: exit 2, one
message naming the file or the command line, and nothing written (issue 23's table, grown
from tests/test_bad_inputs.py's cases)."""

import os
from pathlib import Path

import pytest

from fivebar_drake import catalog
from fivebar_drake.cli import main


ALIAS_BOMB = ('a: &a ["x","x","x","x","x","x","x","x","x"]\n'
              + "".join(f"{c}: &{c} [*{p},*{p},*{p},*{p},*{p},*{p},*{p},*{p},*{p}]\n"
                        for p, c in zip("abcdefgh", "bcdefghi")))
# the content of each hostile file kind by suffix; missing, fifo and folder are not contents
CONTENTS = {".toml": {"binary": b"\xff\xfe\x00 [motor]\n", "not toml": b"[motor\n"},
            ".yaml": {"binary": b"\xff\xfe\x00 maneuvers:\n", "not yaml": b"maneuvers: [\n",
                      "alias bomb": ALIAS_BOMB.encode(),
                      "duplicate key": b"duration_s: 1.0\nduration_s: 2.0\n"}}


def _hostile_file(t, kind, suffix):
    """The path (str) of an input file of the given hostile kind: missing, a FIFO, a folder, or
    a file holding CONTENTS[suffix][kind]."""
    path = t / f"{kind}{suffix}"
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "folder":
        path.mkdir()
    elif kind != "missing":
        path.write_bytes(CONTENTS[suffix][kind])
    return str(path)


CONFIGS = ("missing", "fifo", "binary", "folder", "not toml")
WORDS = {"missing": "not found", "fifo": "not a regular file", "binary": "not UTF-8",
         "folder": "is a folder", "not toml": "not valid TOML"}


@pytest.mark.parametrize("name", catalog.mechanisms())
@pytest.mark.parametrize("command", ["analyze", "simulate"])
@pytest.mark.parametrize("kind", CONFIGS)
def test_bad_parameter_file(name, command, kind, tmp_path, capsys):
    out = tmp_path / "out"
    config = _hostile_file(tmp_path, kind, ".toml")
    assert main([command, "--mechanism", name, "--config", config, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert WORDS[kind] in err and os.path.basename(config) in err, err
    assert not out.exists()


@pytest.mark.parametrize("name", catalog.mechanisms())
@pytest.mark.parametrize("command", ["analyze", "simulate"])
@pytest.mark.parametrize("out_kind", ["empty", "file", "below a file"])
def test_bad_output_path(name, command, out_kind, tmp_path, capsys):
    (tmp_path / "afile").write_text("keep me")
    out = {"empty": "", "file": str(tmp_path / "afile"),
           "below a file": str(tmp_path / "afile" / "sub")}[out_kind]
    assert main([command, "--mechanism", name, "--out", out]) == 2
    assert "--out" in capsys.readouterr().err
    assert (tmp_path / "afile").read_text() == "keep me"


@pytest.mark.parametrize("name", catalog.mechanisms())
@pytest.mark.parametrize("duration", ["nan", "-1", "0", "inf", "1e300"])
def test_bad_duration(name, duration, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["simulate", "--mechanism", name, "--duration", duration, "--out",
                 str(out)]) == 2
    assert "command line" in capsys.readouterr().err
    assert not out.exists()


# a command whose spec is not optional gets its packaged one where the test is not about it
PACKAGED_SPEC = {"codesign": (str(Path(catalog.__file__).parent / "data" / "codesign_demo.yaml"),)}
SPECS = ("missing", "fifo", "binary", "folder", "not yaml", "alias bomb", "duplicate key")
SPEC_WORDS = {"missing": "not found", "fifo": "not a regular file", "binary": "not UTF-8",
              "folder": "is a folder", "not yaml": "not valid YAML", "alias bomb": "alias",
              "duplicate key": "duplicate"}


@pytest.mark.parametrize("command", ["sweep", "envelope", "codesign"])
@pytest.mark.parametrize("kind", SPECS)
def test_bad_spec_file(command, kind, tmp_path, capsys):
    out = tmp_path / "out"
    spec = _hostile_file(tmp_path, kind, ".yaml")
    assert main([command, spec, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert SPEC_WORDS[kind] in err and os.path.basename(spec) in err, err
    assert len(err) < 2000 and "Traceback" not in err
    assert not out.exists()


@pytest.mark.parametrize("command", ["sweep", "envelope", "codesign"])
@pytest.mark.parametrize("out_kind", ["empty", "file", "below a file"])
def test_bad_output_path_of_a_spec_command(command, out_kind, tmp_path, capsys):
    (tmp_path / "afile").write_text("keep me")
    out = {"empty": "", "file": str(tmp_path / "afile"),
           "below a file": str(tmp_path / "afile" / "sub")}[out_kind]
    assert main([command, *PACKAGED_SPEC.get(command, ()), "--out", out]) == 2
    assert "--out" in capsys.readouterr().err
    assert (tmp_path / "afile").read_text() == "keep me"


@pytest.mark.parametrize("command", ["sweep", "envelope", "codesign"])
@pytest.mark.parametrize("workers", ["0", "-1", "1000", "two"])
def test_bad_worker_count(command, workers, tmp_path, capsys):
    out = tmp_path / "out"
    assert main([command, *PACKAGED_SPEC.get(command, ()), "--workers", workers, "--out",
                 str(out)]) == 2
    assert "--workers" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("kind", CONFIGS)
def test_bad_parameter_file_of_optimal(kind, tmp_path, capsys):
    out = tmp_path / "out"
    config = _hostile_file(tmp_path, kind, ".toml")
    assert main(["optimal", "--config", config, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert WORDS[kind] in err and os.path.basename(config) in err, err
    assert not out.exists()


@pytest.mark.parametrize("out_kind", ["empty", "file", "below a file"])
def test_bad_output_path_of_optimal(out_kind, tmp_path, capsys):
    (tmp_path / "afile").write_text("keep me")
    out = {"empty": "", "file": str(tmp_path / "afile"),
           "below a file": str(tmp_path / "afile" / "sub")}[out_kind]
    assert main(["optimal", "--out", out]) == 2
    assert "--out" in capsys.readouterr().err
    assert (tmp_path / "afile").read_text() == "keep me"


@pytest.mark.parametrize("option, value", [
    ("--height", v) for v in ("nan", "-1", "0", "inf", "1e300", "two")] + [
    ("--payload", v) for v in ("nan", "-1", "inf", "1e300", "two")] + [
    ("--top-speed", v) for v in ("gallop", "", "trot,,bound", "none,trot")] + [
    ("--set", v) for v in ("motor.gear_ratio", "motor.gear_ratio=-1", "nosuch.field=1")])
def test_bad_values_of_optimal(option, value, tmp_path, capsys):
    """Every bad value of optimal's options: exit 2 naming the option, nothing written."""
    out = tmp_path / "out"
    assert main(["optimal", option, value, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert option in err or "set" in err, err
    assert "Traceback" not in err and not out.exists()


@pytest.mark.parametrize("kind, words", [
    ("missing folder", "is not a folder"), ("a file", "is not a folder"),
    ("empty folder", "holds no envelope"), ("binary json", "cannot be read"),
    ("not json", "cannot be read"), ("older envelope", "has no 'design_answer'"),
    ("a list", "has no 'design_answer'"), ("fifo json", "holds no envelope")])
def test_index_of_a_hostile_folder(kind, words, tmp_path, capsys):
    """`index DIR` over a folder that holds no outputs, or broken or older ones: exit 2 naming
    the folder or the file, no page written (a FIFO is never opened: it is not an output)."""
    root = tmp_path / "out"
    if kind == "a file":
        root.write_text("keep me")
    elif kind != "missing folder":
        (root / "envelope").mkdir(parents=True)
        target = root / "envelope" / "envelope.json"
        contents = {"binary json": b"\xff\xfe{", "not json": b"{\"verdict\": ",
                    "older envelope": b"{\"verdict\": \"fail\"}", "a list": b"[1, 2]"}
        if kind == "fifo json":
            os.mkfifo(target)
        elif kind in contents:
            target.write_bytes(contents[kind])
    assert main(["index", str(root)]) == 2
    err = capsys.readouterr().err
    assert words in err and str(root) in err, err
    if kind == "missing folder":
        assert not root.exists()
    elif kind == "a file":
        assert root.read_text() == "keep me"
    else:
        assert not (root / "index.html").exists() and not (root / "index.md").exists()
