"""The disk cache runs only code this user's mechdyn wrote (docs/security.md).

Each test uses its own cache directory (MECHDYN_CACHE) and a mechanism declared with a
unique link name, so the in-memory cache never answers and the disk is read.
Reference: a disc of inertia J = 2 under a constant moment 6 turns phi = 3 t^2 / 2, so
after 1 s phi = 1.5 rad and omega = 3 rad/s.
"""
import errno
import json
import os
import stat
import subprocess
import sys
import textwrap
import uuid
from pathlib import Path

import pytest

import mechdyn as md
from mechdyn import cache
from mechdyn.cache import CacheWarning

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests"))
from mounts import can_confine, confined  # noqa: E402  (tests/: a folder, not a package)


def disc(tag):
    phi = md.coordinate("phi")
    mech = md.Mechanism("disc", [phi])
    mech.link(f"disc {tag}", J=2, angle=phi)
    mech.load("drive", 6, along=phi)
    return mech, md.Scene("spin", initial={phi: 0, md.speed(phi): 0}, t_end=1), phi


def run_disc(tag):
    mech, scene, phi = disc(tag)
    result = mech.simulate(scene, {})
    assert result.final(phi) == pytest.approx(1.5, rel=1e-9)
    assert result.final(md.speed(phi)) == pytest.approx(3.0, rel=1e-9)
    return mech.compile(scene).key


@pytest.fixture
def private_cache(tmp_path, monkeypatch):
    directory = tmp_path / "cache"
    monkeypatch.setenv("MECHDYN_CACHE", str(directory))
    return directory


def entry(directory, key):
    return directory / f"scene-{key}.json"


def test_the_directory_and_key_are_private_and_entries_authenticated(private_cache):
    key = run_disc(uuid.uuid4().hex)
    assert stat.S_IMODE(private_cache.stat().st_mode) == 0o700
    if (private_cache / "numba").exists():      # the compiled backend's scene folders too
        assert stat.S_IMODE((private_cache / "numba").stat().st_mode) == 0o700
        assert stat.S_IMODE((private_cache / "numba" / key).stat().st_mode) == 0o700
    assert stat.S_IMODE((private_cache / "key").stat().st_mode) == 0o600
    assert len((private_cache / "key").read_bytes()) == 32
    stored = cache.load(entry(private_cache, key).name)
    assert set(stored) == {"meta", "source"}
    assert [p.name for p in private_cache.iterdir() if p.name.endswith(".tmp")] == []


def compile_elsewhere(tags) -> list:
    """Run the discs of ``tags`` in another process (filling the disk cache, not this
    process's memory; give the cache the session's kernels first, ``share_kernels``);
    their cache keys."""
    script = textwrap.dedent(f"""
        import json, sys
        sys.path.insert(0, {str(ROOT / 'tests' / 'hard')!r})
        from test_cache_trust import run_disc
        print(json.dumps([run_disc(tag) for tag in {list(tags)!r}]))
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          env=dict(os.environ, PYTHONPATH=str(ROOT)))
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


PLANT = '''open({marker!r}, "w").write("planted code ran")\n'''


def signed(name, payload, key):
    import hashlib
    import hmac
    mac = hmac.new(key, name.encode() + b"\0" + payload, hashlib.sha256).hexdigest()
    return b"mechdyn-cache-1 " + mac.encode() + b"\n" + payload


def test_planted_code_never_runs_but_would_if_it_were_authentic(private_cache, tmp_path,
                                                                share_kernels):
    """Four entries with code planted that would create a file: plain JSON (the old
    format), a forged MAC, a MAC under another key, and (the control) one signed with
    this cache's own key. Running the four scenes runs only the control's code; the
    others are rebuilt and stored authentic."""
    share_kernels(private_cache)
    tags = [uuid.uuid4().hex for _ in range(4)]
    keys = compile_elsewhere(tags)
    markers = [tmp_path / f"marker{i}" for i in range(4)]
    paths = [entry(private_cache, key) for key in keys]
    payloads = []
    for path, marker in zip(paths, markers):
        stored = cache.load(path.name)
        stored["source"] = PLANT.format(marker=str(marker)) + stored["source"]
        payloads.append(json.dumps(stored).encode())
    paths[0].write_bytes(payloads[0])
    paths[1].write_bytes(b"mechdyn-cache-1 " + b"0" * 64 + b"\n" + payloads[1])
    paths[2].write_bytes(signed(paths[2].name, payloads[2], os.urandom(32)))
    paths[3].write_bytes(signed(paths[3].name, payloads[3],
                                (private_cache / "key").read_bytes()))
    for tag in tags:
        run_disc(tag)
    assert [m.exists() for m in markers] == [False, False, False, True]
    for path in paths[:3]:
        assert "planted code ran" not in cache.load(path.name)["source"]


def test_damaged_entries_are_rebuilt_and_overwritten(private_cache, share_kernels):
    share_kernels(private_cache)
    tags = [uuid.uuid4().hex for _ in range(4)]
    paths = [entry(private_cache, key) for key in compile_elsewhere(tags)]
    data = paths[0].read_bytes()
    damages = [data[:-10] + bytes([data[-10] ^ 1]) + data[-9:],    # one bit flipped
               paths[1].read_bytes()[:len(data) // 2],              # truncated
               b"",                                                 # emptied
               os.urandom(300)]                                     # garbage
    for path, damaged in zip(paths, damages):
        path.write_bytes(damaged)
        assert cache.load(path.name) is None
    for tag in tags:
        run_disc(tag)
    for path, damaged in zip(paths, damages):
        assert cache.load(path.name) is not None and path.read_bytes() != damaged


def test_an_authentic_but_malformed_entry_is_rebuilt_not_stuck(private_cache):
    """Entries signed with the right key but unusable (missing fields, code that does
    not compile, a field of the wrong type) are rebuilt and overwritten."""
    from mechdyn.compile.compiler import declaration_key
    for broken in ({"meta": {}}, {"meta": {}, "source": "def rhs(:"}, {"source": 5}):
        tag = uuid.uuid4().hex
        name = entry(private_cache, declaration_key(*disc(tag)[:2])).name
        assert cache.store(name, broken)
        run_disc(tag)
        assert set(cache.load(name)) == {"meta", "source"}


def test_an_entry_under_another_name_is_not_taken_for_it(private_cache):
    """An authentic entry copied to another entry's name fails: the MAC covers the name."""
    first, second = run_disc(uuid.uuid4().hex), run_disc(uuid.uuid4().hex)
    entry(private_cache, second).write_bytes(entry(private_cache, first).read_bytes())
    assert cache.load(entry(private_cache, second).name) is None


def test_a_world_writable_directory_is_refused_with_one_warning(private_cache):
    private_cache.mkdir(mode=0o700)
    private_cache.chmod(0o777)
    with pytest.warns(CacheWarning, match="may be written by other users") as warned:
        run_disc(uuid.uuid4().hex)
        run_disc(uuid.uuid4().hex)
    assert len([w for w in warned if w.category is CacheWarning]) == 1
    assert list(private_cache.iterdir()) == []           # nothing read or written there


def test_a_directory_of_another_user_is_refused(private_cache, monkeypatch):
    private_cache.mkdir(mode=0o700)
    monkeypatch.setattr(os, "geteuid", lambda: private_cache.stat().st_uid + 1)
    with pytest.warns(CacheWarning, match="owned by user id"):
        run_disc(uuid.uuid4().hex)
    assert list(private_cache.iterdir()) == []


@pytest.mark.skipif(not hasattr(os, "chown") or os.geteuid() != 0,
                    reason="only root can give a directory to another user")
def test_a_directory_really_owned_by_another_user_is_refused(private_cache):
    private_cache.mkdir(mode=0o700)
    os.chown(private_cache, 65534, 65534)
    with pytest.warns(CacheWarning, match="owned by user id 65534"):
        run_disc(uuid.uuid4().hex)
    assert list(private_cache.iterdir()) == []


def test_a_key_readable_by_others_is_replaced_and_its_entries_rebuilt(private_cache):
    key = run_disc(uuid.uuid4().hex)
    (private_cache / "key").chmod(0o644)
    with pytest.warns(CacheWarning, match="key file may be read or written by other"):
        assert cache.load(entry(private_cache, key).name) is None
        run_disc(uuid.uuid4().hex)
    assert stat.S_IMODE((private_cache / "key").stat().st_mode) == 0o600
    assert cache.load(entry(private_cache, key).name) is None      # signed by the old key


@pytest.mark.parametrize("code, said", [(errno.ENOSPC, "the disk is full"),
                                        (errno.EROFS, "it is read-only")])
def test_a_full_or_read_only_disk_degrades_to_no_disk_cache_with_one_warning(
        private_cache, monkeypatch, code, said):
    """Writes fail with ENOSPC or EROFS (injected where the cache creates its files):
    runs go on, one warning, no temporary files left behind."""
    run_disc(uuid.uuid4().hex)                             # the key exists already

    def failing(path, data):
        raise OSError(code, os.strerror(code), str(path))
    monkeypatch.setattr(cache, "_write_new", failing)
    with pytest.warns(CacheWarning, match=said) as warned:
        for _ in range(3):
            run_disc(uuid.uuid4().hex)
    assert len([w for w in warned if w.category is CacheWarning]) == 1
    assert [p for p in private_cache.iterdir() if p.suffix == ".tmp"] == []


@pytest.mark.slow            # the process compiles the kernels in memory (20-50 s)
def test_a_file_size_limit_degrades_to_no_disk_cache_in_a_real_process(private_cache):
    """RLIMIT_FSIZE makes every cache write beyond 64 bytes fail for real (as a full
    disk does), numba's files of the kernels included: the command still succeeds
    (compiling the kernels for the process), with one warning line."""
    resource = pytest.importorskip("resource")
    import signal

    def limit():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (64, 64))

    done = subprocess.run([sys.executable, "-m", "mechdyn.cli.command", "simulate",
                           str(ROOT / "models" / "shoe_brake.py"), "--scene", "braking"],
                          capture_output=True, text=True, preexec_fn=limit,
                          env=dict(os.environ, PYTHONPATH=str(ROOT),
                                   PYTHONDONTWRITEBYTECODE="1"))
    assert done.returncode == 0, done.stderr
    assert "t = 50 s" in done.stdout
    assert done.stderr.count("mechdyn: warning:") == 1 and "cannot write" in done.stderr
    # numba's files of the kernels go to the same folder (issue 37), and are not kept
    assert [p.name for p in private_cache.rglob("*") if p.is_file()] == ["key"]


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes to read-only directories")
def test_a_read_only_directory_degrades_to_no_disk_cache(private_cache):
    run_disc(uuid.uuid4().hex)
    private_cache.chmod(0o500)
    try:
        with pytest.warns(CacheWarning, match="read-only"):
            run_disc(uuid.uuid4().hex)
    finally:
        private_cache.chmod(0o700)


@pytest.mark.slow            # the process compiles the kernels in memory (20-50 s)
def test_a_read_only_mount_degrades_to_no_disk_cache_in_a_real_process(private_cache):
    """The cache folder mounted read-only (as a shared cache on a cluster's nodes; a
    mount binds root too, where permissions do not): the command succeeds, compiling
    for the process, with one warning that says why."""
    run_disc(uuid.uuid4().hex)                             # the folder and its key
    if not can_confine(private_cache):
        pytest.skip("no mount namespaces here (unshare --mount)")
    before = sorted(p.name for p in private_cache.rglob("*"))
    done = subprocess.run(confined([sys.executable, "-m", "mechdyn.cli.command", "simulate",
                                    str(ROOT / "models" / "shoe_brake.py"),
                                    "--scene", "braking"], private_cache, "read-only"),
                          capture_output=True, text=True,
                          env=dict(os.environ, PYTHONPATH=str(ROOT),
                                   PYTHONDONTWRITEBYTECODE="1"))
    assert done.returncode == 0, done.stderr
    assert "t = 50 s" in done.stdout
    assert done.stderr.count("mechdyn: warning:") == 1, done.stderr
    assert "cannot write to it (it is read-only)" in done.stderr
    assert sorted(p.name for p in private_cache.rglob("*")) == before


LOADED_FROM_DISK = textwrap.dedent("""
    import sys
    from mechdyn.cli.command import main
    assert main(["simulate", sys.argv[1], "--scene", "braking"]) == 0
    modules = [m for n, m in sys.modules.items() if n.startswith("mechdyn_model_")]
    dispatchers = [f for m in modules for f in vars(m).values() if hasattr(f, "stats")]
    print(len(modules), sum(sum(f.stats.cache_hits.values()) for f in dispatchers),
          sum(sum(f.stats.cache_misses.values()) for f in dispatchers))
""")


@pytest.mark.slow            # three processes, each loading the kernels (3-5 s)
def test_a_read_only_mount_that_holds_the_scene_is_read_and_nothing_compiled(
        private_cache, share_kernels):
    """A shared cache mounted read-only on a cluster's nodes, filled beforehand: the
    scene's compiled functions are loaded from it (numba's cache hits, no misses),
    without a warning."""
    if not can_confine(private_cache.parent):
        pytest.skip("no mount namespaces here (unshare --mount)")
    share_kernels(private_cache)
    command = [sys.executable, "-c", LOADED_FROM_DISK, str(ROOT / "models" / "shoe_brake.py")]
    env = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONDONTWRITEBYTECODE="1")
    filled = subprocess.run(command, capture_output=True, text=True, env=env)
    assert filled.returncode == 0, filled.stderr
    read = subprocess.run(confined(command, private_cache, "read-only"),
                          capture_output=True, text=True, env=env)
    assert read.returncode == 0, read.stderr
    modules, hits, misses = map(int, read.stdout.split()[-3:])
    assert modules == 1 and hits > 0 and misses == 0, read.stdout
    assert "warning" not in read.stderr, read.stderr


@pytest.mark.slow
def test_concurrent_processes_fill_one_cache_without_damage(private_cache, share_kernels):
    """Three processes compile the same scene into an empty cache at once: all succeed,
    the entry is authentic, no temporary file is left."""
    share_kernels(private_cache)
    command = [sys.executable, "-m", "mechdyn.cli.command", "simulate",
               str(ROOT / "models" / "shoe_brake.py"), "--scene", "braking"]
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    runs = [subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, env=env) for _ in range(3)]
    outputs = [run.communicate() for run in runs]
    assert [run.returncode for run in runs] == [0, 0, 0], outputs
    entries = [p for p in private_cache.iterdir() if p.name.startswith("scene-")]
    assert len(entries) == 1 and cache.load(entries[0].name) is not None
    assert [p for p in private_cache.iterdir() if p.name.endswith(".tmp")] == []


def test_a_key_that_is_a_symbolic_link_is_replaced(private_cache, tmp_path):
    key = run_disc(uuid.uuid4().hex)
    elsewhere = tmp_path / "their-key"
    elsewhere.write_bytes((private_cache / "key").read_bytes())
    (private_cache / "key").unlink()
    (private_cache / "key").symlink_to(elsewhere)
    with pytest.warns(CacheWarning, match="key file is a symbolic link"):
        assert cache.load(entry(private_cache, key).name) is None
    assert not (private_cache / "key").is_symlink()


@pytest.mark.parametrize("name", ["", ".hidden", "key", "a/b", "..", "x\0y"])
def test_entry_names_are_plain_file_names(private_cache, name):
    with pytest.raises(ValueError, match="plain file name"):
        cache.store_bytes(name, b"data")


def test_other_artifacts_round_trip_as_authenticated_bytes(private_cache):
    blob = os.urandom(1000)
    assert cache.store_bytes("warm-start.bin", blob)
    assert cache.load_bytes("warm-start.bin") == blob
    assert cache.load_bytes("other.bin") is None
