"""cli.system.supervisor.logs: run folders, their names and their pruning."""

from __future__ import annotations

from turtlectl.cli.system.supervisor import logs


def test_run_folders_beyond_keep_logs_are_removed_oldest_first(tmp_path):
    names = [f"2026-01-0{d}-10-00-00-{100 + d}" for d in range(1, 8)]  # pids 101..107
    for name in names:
        (tmp_path / name).mkdir()
        (tmp_path / name / "sim.log").write_text("x")
    (tmp_path / "notes").mkdir()  # not a run folder: never touched
    (tmp_path / "2026-01-09-10-00-00-1.txt").write_text("")  # a file, not a folder
    current = logs.run_folder(tmp_path, pid=999)
    current.mkdir()
    still_running = {102}  # a launch that is still writing: kept whatever its age
    removed = logs.prune(tmp_path, 3, current, running=lambda pid: pid in still_running)
    assert sorted(p.name for p in removed) == [names[0], names[2], names[3], names[4]]
    left = sorted(p.name for p in tmp_path.iterdir())
    assert left == sorted([names[1], names[5], names[6], current.name, "notes", "2026-01-09-10-00-00-1.txt"])
    assert logs.prune(tmp_path, 0, current) == []  # 0: keep them all


def test_run_folder_names_sort_by_time_then_pid():
    assert logs.RUN_RE.match(logs.run_folder(logs.default_parent(), now=0.0, pid=42).name)
    assert logs.default_parent().parts[-2:] == (".turtlectl", "log")
