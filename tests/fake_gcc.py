"""A gcc on PATH that fails as a compiler does: exit 1 after its last lines on stderr."""

#: the two lines the fake gcc prints, as the package joins them
GCC_SAYS = "cc1: fatal error: out of luck / compilation terminated."


def install_failing_gcc(tmp_path, monkeypatch):
    """Put the failing gcc first (and alone) on PATH and point ``MOL_SHELL_CACHE`` at an empty folder."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    (bin_dir / "gcc").write_text("#!/bin/sh\necho 'cc1: fatal error: out of luck' >&2\n"
                                 "echo 'compilation terminated.' >&2\nexit 1\n")
    (bin_dir / "gcc").chmod(0o755)
    monkeypatch.setenv("PATH", str(bin_dir))
    monkeypatch.setenv("MOL_SHELL_CACHE", str(tmp_path / "cache"))
