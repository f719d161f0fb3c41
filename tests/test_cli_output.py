"""``-o``: the targets a command writes to (a failed run keeps the old file; missing directories,
named pipes, symbolic links, empty names, read-only files).

Through click's CliRunner."""

from __future__ import annotations

from .clirun import run, run_split


def test_failed_run_keeps_the_old_file(poses, tmp_path):
    path, _, _ = poses
    out = tmp_path / "o.csv"
    out.write_text("precious\n")
    result = run("interpolate", path, "-o", out, "--mode", "screw", "--delta", 1)
    assert result.exit_code == 1
    assert out.read_text() == "precious\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o.csv", "poses.json"]


def test_output_into_missing_directory(poses, tmp_path):
    path, _, _ = poses
    result = run("interpolate", path, "-o", tmp_path / "nowhere" / "o.csv")
    assert result.exit_code == 1
    assert "cannot write" in result.output


def test_output_into_a_named_pipe_is_written_directly(poses, tmp_path):
    import os
    import threading

    path, _, _ = poses
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    received = []
    reader = threading.Thread(target=lambda: received.append(fifo.read_bytes()))
    reader.start()
    result = run("interpolate", path, "--samples", 3, "-o", fifo)
    reader.join(timeout=30)
    assert result.exit_code == 0
    assert received[0].decode().splitlines()[0] == "t,tx,ty,tz,qw,qx,qy,qz"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe", "poses.json"]


def test_output_through_a_symbolic_link_replaces_the_file_it_points_to(poses, tmp_path):
    path, _, _ = poses
    target = tmp_path / "run-42.csv"
    target.write_text("old\n")
    link = tmp_path / "latest.csv"
    link.symlink_to(target.name)
    assert run("interpolate", path, "--samples", 3, "-o", link).exit_code == 0
    assert link.is_symlink() and target.read_text().startswith("t,tx")


def test_output_to_an_empty_name_or_a_read_only_file(poses, tmp_path):
    path, _, _ = poses
    result = run_split("interpolate", path, "-o", "")
    assert result.exit_code == 1 and result.stderr == "Error: cannot write to an empty file name\n"
    locked = tmp_path / "locked.csv"
    locked.write_text("keep\n")
    locked.chmod(0o444)
    result = run_split("interpolate", path, "-o", locked)
    assert result.exit_code == 1
    assert (
        result.stderr
        == f"Error: cannot write {locked}: Permission denied (the file is read-only)\n"
    )
    assert locked.read_text() == "keep\n"
