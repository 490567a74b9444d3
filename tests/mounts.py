"""A process that sees one folder read-only or full, for the tests of the cache on such
folders: permissions do not stop root (CI's user), a mount does. The process runs in a
mount namespace of its own (``unshare --mount``), so the rest of the machine sees no
change; where the system does not allow that, :func:`can_confine` says so.
"""
import subprocess
from pathlib import Path

_SEED = '{ [ ! -d "$1" ] || cp -a "$1/." "$0/"; }'       # a copy of the seed, if one


def _script(how, seed) -> str:
    if how == "read-only":      # as a shared cache mounted read-only on a cluster's nodes
        return f'{_SEED} && mount --bind "$0" "$0" && mount -o remount,ro,bind "$0"'
    if how == "full":           # a tmpfs just big enough for the seed, filled to its last byte
        return (f'mount -t tmpfs -o size={_tmpfs_kib(seed)}k,mode=0700 tmpfs "$0" && '
                f'{_SEED} && {{ dd if=/dev/zero of="$0/filler" bs=4k 2>/dev/null || true; }}')
    raise ValueError(f"how: 'read-only' or 'full', not {how!r}")


def _tmpfs_kib(seed) -> int:
    """KiB for the seed's files in tmpfs's 4 KiB pages, and 1 MiB more."""
    files = Path(seed).rglob("*") if seed else ()
    return 1024 + sum(4 + -(-p.stat().st_size // 4096) * 4 for p in files)


def confined(command, folder, how, seed=None) -> list:
    """``command`` (and its children, e.g. a nanny's worker) where ``folder`` is
    ``"read-only"`` or ``"full"``, holding a copy of the folder ``seed`` (e.g. compiled
    kernels) if given."""
    return ["unshare", "--mount", "sh", "-c", f'{_script(how, seed)} && shift && exec "$@"',
            str(folder), str(seed or ""), *command]


def can_confine(folder) -> bool:
    """Whether this process may make mount namespaces (root, or a permitting sandbox)."""
    try:
        done = subprocess.run(confined(["true"], folder, "full"), capture_output=True,
                              timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return done.returncode == 0
