"""Result folders: one result per folder, atomic files, the usual file mode."""
import os
import stat

import pytest
from matplotlib.figure import Figure

from hga_jax.errors import ConfigError
from hga_jax.host.output import (atomic_write, check_folder, json_writer, result_files_in,
                            write_result)
from hga_jax.host.plots import save_figure


def _mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


@pytest.fixture()
def umask():
    """Run a test under a chosen umask, restoring the old one."""
    old = os.umask(0o022)
    yield lambda m: os.umask(m)
    os.umask(old)


@pytest.mark.parametrize("mask,mode", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_files_get_the_mode_open_would_give(tmp_path, umask, mask, mode):
    umask(mask)
    fig = Figure()
    fig.add_subplot().plot([0, 1], [0, 1])
    written = write_result(str(tmp_path / "r"), {"result.json": (json_writer({"a": 1}), False),
                                                 "path.png": (lambda fh: fig.savefig(fh), True)},
                           force=False)
    assert [_mode(p) for p in written] == [mode, mode]
    assert _mode(save_figure(fig, tmp_path / "f.png")) == mode
    with open(tmp_path / "plain", "w"):
        pass
    assert _mode(tmp_path / "plain") == mode  # the same as a file made by open()


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "result.json"
    target.write_text("old")

    def broken(fh):
        fh.write("half")
        raise RuntimeError("disk on fire")

    with pytest.raises(RuntimeError):
        atomic_write(str(target), broken)
    assert target.read_text() == "old" and os.listdir(tmp_path) == ["result.json"]


def test_a_folder_holds_one_result(tmp_path):
    out = str(tmp_path / "r")
    first = {n: (json_writer(n), False) for n in
             ("result.json", "history.csv", "path.png", "convergence.png", "path_run3.png")}
    write_result(out, first, force=False)
    (tmp_path / "r" / "notes.txt").write_text("mine")
    with pytest.raises(ConfigError, match=r"r: output folder: already holds a result "
                       r"\(convergence\.png, history\.csv, path\.png, path_run3\.png, "
                       r"result\.json\); use --force"):
        write_result(out, {"result.json": (json_writer(1), False)}, force=False)
    write_result(out, {"result.json": (json_writer(2), False)}, force=True)
    # the earlier result's files are gone; the user's own file stays
    assert sorted(os.listdir(out)) == ["notes.txt", "result.json"]
    assert result_files_in(out) == ["result.json"]


def test_check_folder_creates_nothing_and_names_the_problem(tmp_path):
    check_folder(str(tmp_path / "a" / "b"), force=False)
    assert not (tmp_path / "a").exists()
    (tmp_path / "file").write_text("x")
    with pytest.raises(ConfigError, match="file: output folder: exists and is a file, not a folder"):
        check_folder(str(tmp_path / "file"), force=True)
    with pytest.raises(ConfigError, match=r"file/sub: output folder: .*file is a file, not a "
                       "folder, so nothing can be made under it"):
        check_folder(str(tmp_path / "file" / "sub"), force=False)
    if os.geteuid() != 0:  # root may write anywhere
        ro = tmp_path / "ro"
        ro.mkdir(mode=0o555)
        with pytest.raises(ConfigError, match="is not writable"):
            check_folder(str(ro / "x"), force=False)
