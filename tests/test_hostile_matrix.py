"""Every subcommand of every mechanism under the same classes of hostile input: exit 2, one
message naming the file or the command line, and nothing written (issue 23's table, grown
from tests/test_bad_inputs.py's cases)."""

import os

import pytest

from fivebar_drake import catalog
from fivebar_drake.cli import main


def _config(t, kind):
    path = t / f"{kind}.toml"
    if kind == "missing":
        return str(path)
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "binary":
        path.write_bytes(b"\xff\xfe\x00 [motor]\n")
    elif kind == "folder":
        path.mkdir()
    elif kind == "not toml":
        path.write_text("[motor\n")
    return str(path)


CONFIGS = ("missing", "fifo", "binary", "folder", "not toml")
WORDS = {"missing": "not found", "fifo": "not a regular file", "binary": "not UTF-8",
         "folder": "is a folder", "not toml": "not valid TOML"}


@pytest.mark.parametrize("name", catalog.MECHANISMS)
@pytest.mark.parametrize("command", ["analyze", "simulate"])
@pytest.mark.parametrize("kind", CONFIGS)
def test_bad_parameter_file(name, command, kind, tmp_path, capsys):
    out = tmp_path / "out"
    config = _config(tmp_path, kind)
    assert main([command, "--mechanism", name, "--config", config, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert WORDS[kind] in err and os.path.basename(config) in err, err
    assert not out.exists()


@pytest.mark.parametrize("name", catalog.MECHANISMS)
@pytest.mark.parametrize("command", ["analyze", "simulate"])
@pytest.mark.parametrize("out_kind", ["empty", "file", "below a file"])
def test_bad_output_path(name, command, out_kind, tmp_path, capsys):
    (tmp_path / "afile").write_text("keep me")
    out = {"empty": "", "file": str(tmp_path / "afile"),
           "below a file": str(tmp_path / "afile" / "sub")}[out_kind]
    assert main([command, "--mechanism", name, "--out", out]) == 2
    assert "--out" in capsys.readouterr().err
    assert (tmp_path / "afile").read_text() == "keep me"


@pytest.mark.parametrize("name", catalog.MECHANISMS)
@pytest.mark.parametrize("duration", ["nan", "-1", "0", "inf", "1e300"])
def test_bad_duration(name, duration, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["simulate", "--mechanism", name, "--duration", duration, "--out",
                 str(out)]) == 2
    assert "command line" in capsys.readouterr().err
    assert not out.exists()
