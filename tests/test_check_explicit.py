"""Files named explicitly on the command line: rostest / `.xml` launch files are checked."""

import subprocess
import sys
from pathlib import Path


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "tvl_lsp", *args], capture_output=True, text=True, cwd=cwd)


def test_explicit_xml_launch_file_is_checked(tmp_path: Path):
    f = tmp_path / "test-undefined.xml"
    f.write_text('<?xml version="1.0"?>\n<launch>\n  <node pkg="a" type="b" name="n" args="$(arg nope)"/>\n</launch>\n')
    r = run("--check", str(f))
    assert r.returncode == 1, r.stdout + r.stderr
    assert "undefined-arg" in r.stdout
    assert "1 file(s) checked" in r.stderr


def test_explicit_xml_that_is_not_a_launch_file_is_skipped(tmp_path: Path):
    f = tmp_path / "other.xml"
    f.write_text("<robot><link name='x'/></robot>\n")
    r = run("--check", str(f))
    assert r.returncode == 0
    assert "0 file(s) checked" in r.stderr


def test_xml_inside_a_folder_walk_is_not_taken_for_a_launch_file(tmp_path: Path):
    (tmp_path / "urdf.xml").write_text("<launch><node name='x'/></launch>\n")
    r = run("--check", str(tmp_path))
    assert r.returncode == 0
    assert "0 file(s) checked" in r.stderr
