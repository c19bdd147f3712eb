"""Files named explicitly on the command line: rostest / `.xml` launch files are checked (in
folders too, the other XML files counted); an `.xml` / `.test` file named explicitly is checked as
the launch file it is said to be (one whose root is not <launch> gets roslaunch's own error, as
roslaunch rejects it: issue 27, class 7); any other file that is not checked gets a diagnostic of
the report (`file-not-checked`: what it was taken to be, why it was skipped), an error (a
warning for a Python launch file, which tvl-lsp does not run; ``--strict`` makes that fail too).
A folder's walk passes over such files silently."""

from pathlib import Path
from types import SimpleNamespace

import pytest

from tvl_lsp.main import main


@pytest.fixture
def run(capsys, monkeypatch):
    """``tvl-lsp ARGS`` in this process (the console entry point): returncode, stdout, stderr."""
    def run(*args, cwd=None):
        if cwd is not None:
            monkeypatch.chdir(cwd)
        code = main(list(args))
        out, err = capsys.readouterr()
        return SimpleNamespace(returncode=code, stdout=out, stderr=err)
    return run


def test_explicit_xml_launch_file_is_checked(run, tmp_path: Path):
    f = tmp_path / "test-undefined.xml"
    # $(arg nope) with only 'Nope' declared: a typo, an error
    f.write_text('<?xml version="1.0"?>\n<launch>\n  <arg name="Nope" default="x"/>\n'
                 '  <node pkg="a" type="b" name="n" args="$(arg nope)"/>\n</launch>\n')
    r = run("--check", str(f))
    assert r.returncode == 1, r.stdout + r.stderr
    assert "undefined-arg" in r.stdout
    assert "1 file(s) checked" in r.stderr


def _notices(stderr: str) -> list[str]:
    return [l for l in stderr.splitlines() if l.startswith("tvl-lsp --check: ")]


def test_explicit_xml_that_is_not_a_launch_file_is_reported(run, tmp_path: Path):
    f = tmp_path / "other.xml"
    f.write_text("<?xml version='1.0'?>\n<!-- a robot -->\n<robot><link name='x'/></robot>\n")
    r = run("--check", str(f))
    assert r.returncode == 1
    # roslaunch other.xml: "Invalid roslaunch XML syntax: no root <launch> tag"; on the root tag
    assert f"{f}:3:2: error[no-launch-root]" in r.stdout, r.stdout
    assert "1 file(s) checked" in r.stderr and _notices(r.stderr) == []
    f.write_text("<?xml version='1.0'?>\n<!-- tvl-lsp: dialect=ros1 -->\n<robot><link name='x'/></robot>\n")
    r = run("--check", str(f))
    assert r.returncode == 1 and f"{f}:3:2: error[no-launch-root] Invalid roslaunch XML syntax: no root <launch> " \
        "tag" in r.stdout, r.stdout


def _reported(stdout: str, f: Path) -> list[str]:
    return [line for line in stdout.splitlines() if line.startswith(f"{f}:")]


@pytest.mark.parametrize("name,content,taken_to_be,severity", [
    ("notes.txt", "hello\n", "taken to be a .txt file; --check reads only models (.tvl, .uvl, .dimacs), launch files",
     "error"),
    ("README", "hello\n", "taken to be a file without a suffix; --check reads only", "error"),
    ("params.yaml", "rate: 10\n", "taken to be a plain YAML file, not a HAROS project file: it has no "
                                   "top-level `configurations:`", "error"),
    ("package.xml", "<package format='2'><name>p</name></package>\n",
     "taken to be a catkin package manifest: it is read for package names, not checked", "error"),
    ("blob.bin", b"\x00\x01\x02", "taken to be a binary file; --check reads only", "error"),
])
def test_every_kind_of_unchecked_file_is_named(run, tmp_path: Path, name, content, taken_to_be, severity):
    f = tmp_path / name
    f.write_bytes(content if isinstance(content, bytes) else content.encode())
    r = run("--check", str(f))
    assert r.returncode == (1 if severity == "error" else 0), r.stdout + r.stderr
    (line,) = _reported(r.stdout, f)
    assert line.startswith(f"{f}:1:1: {severity}[file-not-checked] {name} is not checked: {taken_to_be}"), line
    assert "0 file(s) checked, 1 named file(s) not checked" in r.stderr
    assert run("--check", "--strict", str(f)).returncode == 1
    r = run("--check", "--format", "json", str(f))
    assert '"file-not-checked"' in r.stdout


def test_a_python_launch_file_named_is_checked(run, tmp_path: Path):
    """A .launch.py file is a launch file (#25): checked, never run.  Without
    generate_launch_description() ros2 launch cannot load it: that is its error."""
    f = tmp_path / "bringup.launch.py"
    f.write_text("from launch import LaunchDescription\n")
    r = run("--check", str(f))
    assert r.returncode == 1 and "generate_launch_description()" in r.stdout
    assert "file-not-checked" not in r.stdout
    f.write_text("from launch import LaunchDescription\n\n\ndef generate_launch_description():\n"
                 "    return LaunchDescription([])\n")
    assert run("--check", str(f)).returncode == 0


def test_checked_and_unchecked_files_together(run, tmp_path: Path):
    (tmp_path / "m.tvl").write_text("root R { group allOf { opt A } }\n")
    (tmp_path / "notes.md").write_text("# notes\n")
    (tmp_path / "haros.yaml").write_text("configurations:\n  {lf: p/launch/a.launch, tvl: p/m.tvl}\n")
    r = run("--check", "m.tvl", "notes.md", "haros.yaml", cwd=tmp_path)
    assert [line.split(":")[0] for line in r.stdout.splitlines() if "file-not-checked" in line] == \
        ["notes.md"]   # (paths printed relative to the working directory)
    assert "2 file(s) checked, 1 named file(s) not checked" in r.stderr
    # a folder walk does not report what it passes over
    r = run("--check", str(tmp_path))
    assert "file-not-checked" not in r.stdout and "named file(s) not checked" not in r.stderr


def test_folder_walk_finds_rostest_and_xml_launch_files_and_counts_the_other_xml(run, tmp_path: Path):
    (tmp_path / "bringup.xml").write_text("<?xml version='1.0'?>\n<!-- a launch file named .xml -->\n"
                                          "<launch><node name='x'/></launch>\n")
    (tmp_path / "ok.test").write_text("<launch><test test-name='t' pkg='p' type='t'/></launch>\n")
    (tmp_path / "robot.xml").write_text("<robot><link name='x'/></robot>\n")
    (tmp_path / "package.xml").write_text("<package><name>p</name></package>\n")
    r = run("--check", str(tmp_path))
    assert r.returncode == 1, r.stdout + r.stderr
    assert "bringup.xml" in r.stdout and "missing-attribute" in r.stdout
    assert "ok.test" not in r.stdout
    assert "2 file(s) checked; 1 XML file(s) skipped: their root element is not <launch>" in r.stderr


@pytest.mark.parametrize("name", ["robot.dimacs", "robot.cnf"])
def test_a_dimacs_model_named_on_the_command_line_is_checked(run, tmp_path: Path, name):
    f = tmp_path / name
    f.write_text("c 1 A\nc 2 B\np cnf 2 2\n1 0\n-1 -2 0\n")
    r = run("--check", str(f))
    assert r.returncode == 0, r.stderr
    assert _notices(r.stderr) == []
    assert "dead-feature" in r.stdout and f"{name}:2:" in r.stdout  # B is dead, on its `c` line
