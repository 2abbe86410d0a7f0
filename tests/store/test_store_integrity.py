"""A store that knows its chunks (issue 38, docs/store.md "Damage"): chunks moved between
stores and places, checkpoints exchanged, folders replaced, rows cut; a resumed or read run
either equals the original bit for bit or stops with a StoreError naming the store and what
is damaged. Format-2 stores (the build before) still resume and read, as a legacy format."""

from __future__ import annotations

import json
import shutil
import struct
import zlib
from pathlib import Path
from typing import Any

import numpy as np
import pytest

zarr = pytest.importorskip("zarr")

import duhamel  # noqa: E402
from duhamel import elements as el  # noqa: E402
from duhamel import loads as L  # noqa: E402
from duhamel.store import Store, StoreError, resume  # noqa: E402
from duhamel.store._codec import pack, unpack  # noqa: E402

#: 4 segments of 1024 rows, the last one short (4,001 rows).
KW = {"t_end": 40.0, "dt": 0.01, "energy": True}


def system(amplitude: float) -> duhamel.System:
    """The same grid and arrays for every amplitude, different numbers."""
    s = duhamel.System(np.eye(2), [[2.0, -1.0], [-1.0, 1.0]], zeta=0.02)
    s.add(el.Bilinear(0, None, k=0.5, fy=0.05, alpha=0.1))
    s.add_load(L.Harmonic(1, amplitude=amplitude, omega=0.9))
    return s


def content(sol: duhamel.Solution) -> dict[str, np.ndarray]:
    """Every stored history of `sol`, read."""
    out = {"t": sol.t, "x": sol.x, "v": sol.v, "a": sol.a}
    out.update(q=sol.modal.q, qv=sol.modal.v, loads=sol.modal.load_values)
    for i, h in enumerate(sol.elements):
        out.update({f"e{i}x": h.x, f"e{i}v": h.v, f"e{i}f": h.force})
    out.update(damping=sol.energy.damping, work=sol.energy.elements)
    return {k: np.asarray(v) for k, v in out.items()}


def equal(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> bool:
    return a.keys() == b.keys() and all(
        a[k].shape == b[k].shape and np.array_equal(a[k], b[k]) for k in a
    )


def stop_after(step0: int) -> Any:
    def progress(step: int, total: int, t: float) -> None:
        if step > step0:
            raise RuntimeError("stopped")

    return progress


@pytest.fixture(scope="module")
def stores(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """Stores A and B (same grid, other numbers), complete, and each stopped after its second
    checkpoint (``A_stop`` is A before it was resumed: the same store, earlier)."""
    root = tmp_path_factory.mktemp("stores")
    out: dict[str, Any] = {"root": root}
    for name, amplitude in (("A", 0.3), ("B", 0.25)):
        path = root / name
        with pytest.raises(RuntimeError, match="stopped"):
            where = Store(path, segment_bytes=1)
            duhamel.solve(system(amplitude), duhamel.Semianalytic(), **KW, store=where,
                          progress=stop_after(2100))  # fmt: skip
        shutil.copytree(path, root / f"{name}_stop")
        out[name] = content(resume(path))
        ref = content(duhamel.solve(system(amplitude), duhamel.Semianalytic(), **KW))
        # a stored run is the in-memory run: bit for bit, its energy totals (carried from
        # segment to segment) to round-off (docs/store.md)
        energy = ("damping", "work")
        assert equal({k: v for k, v in out[name].items() if k not in energy},
                     {k: v for k, v in ref.items() if k not in energy})  # fmt: skip
        for k in energy:
            np.testing.assert_allclose(out[name][k], ref[k], rtol=0, atol=1e-14)
    assert not equal(out["A"], out["B"])
    return out


def chunk(path: Path, name: str, i: int) -> Path:
    """The file of chunk `i` of the data array `name` (it may not exist)."""
    meta = json.loads((path / "data" / name / "zarr.json").read_text())
    return path / "data" / name / "c" / str(i) / "/".join(["0"] * (len(meta["shape"]) - 1))


def arrays(path: Path) -> list[str]:
    return sorted(p.name for p in (path / "data").iterdir() if p.is_dir())


def slots(path: Path) -> list[Any]:
    group = zarr.open_group(path)["checkpoints"]
    return [unpack(group[k][...]) for k in ("0", "1")]


def put_slot(path: Path, k: int, raw: bytes) -> None:
    """Writes `raw` as checkpoint slot `k` (as the store writes a slot)."""
    blob = np.frombuffer(raw, dtype=np.uint8)
    group = zarr.open_group(path)["checkpoints"]
    group.create_array(str(k), shape=blob.shape, dtype="u1", chunks=blob.shape,
                       compressors=None, overwrite=True)  # fmt: skip
    group[str(k)][...] = blob


def resumed_or_refused(path: Path, reference: dict[str, np.ndarray]) -> str:
    """Resumes `path`: equal to `reference`, or a StoreError naming the store."""
    try:
        sol = resume(path)
    except StoreError as exc:
        assert path.name in str(exc) and "damaged" in str(exc), exc
        return "refused"
    assert equal(content(sol), reference), "a damaged store resumed to other numbers"
    return "equal"


# -- damage, one kind at a time ----------------------------------------------------------------


def _copy(stores: dict[str, Any], source: str, name: str) -> Path:
    path = stores["root"] / "cases" / name
    shutil.rmtree(path, ignore_errors=True)
    shutil.copytree(stores["root"] / source, path)
    return path


def _foreign_chunk(a: Path, b: Path, name: str, i: int) -> None:
    shutil.copyfile(chunk(b, name, i), chunk(a, name, i))


def _swap(a: Path, _b: Path, name: str, i: int) -> None:
    j = (i + 1) % 3
    one, two = chunk(a, name, i).read_bytes(), chunk(a, name, j).read_bytes()
    chunk(a, name, i).write_bytes(two)
    chunk(a, name, j).write_bytes(one)


def _other_array(a: Path, _b: Path, name: str, i: int) -> None:
    other = "v" if name != "v" else "x"
    shutil.copyfile(chunk(a, other, i), chunk(a, name, i))


def _folder(what: str, source: str) -> Any:
    def damage(a: Path, b: Path) -> None:
        origin = b.parent / source
        shutil.rmtree(a / what)
        shutil.copytree(origin / what, a / what)

    return damage


CASES = {
    "data/ of another complete store": _folder("data", "B"),
    "data/ of another stopped store": _folder("data", "B_stop"),
    "data/ and manifest of another store": lambda a, b: (
        _folder("data", "B")(a, b),
        _folder("manifest", "B")(a, b),
    ),
    "manifest of another store": _folder("manifest", "B"),
    "checkpoints of another store": _folder("checkpoints", "B"),
    "checkpoints of another stopped store": _folder("checkpoints", "B_stop"),
    "checkpoints of this store, earlier": _folder("checkpoints", "A_stop"),
    "data/ of this store, earlier": _folder("data", "A_stop"),
}


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("target", ["A", "A_stop"])
def test_moved_checkpoints_and_folders(stores, case, target):
    a = _copy(stores, target, f"{target}-{case}")
    CASES[case](a, stores["root"] / ("B" if target == "A" else "B_stop"))
    outcome = resumed_or_refused(a, stores["A"])
    harmless = case == "checkpoints of this store, earlier" or (
        case == "data/ of this store, earlier" and target == "A_stop"
    )
    assert outcome == ("equal" if harmless else "refused"), outcome


@pytest.mark.parametrize("move", [_foreign_chunk, _swap, _other_array])
@pytest.mark.parametrize("name", ["x", "element_force", "modal_q"])
@pytest.mark.parametrize("target", ["A", "A_stop"])
def test_moved_chunks(stores, move, name, target):
    a = _copy(stores, target, f"{target}-{move.__name__}-{name}")
    move(a, stores["root"] / ("B" if target == "A" else "B_stop"), name, 1)
    assert resumed_or_refused(a, stores["A"]) == "refused"


def test_the_manifest_is_a_zarr_array_of_the_chunks_digests(stores):
    """Its rows (written straight to their chunk files) read back through zarr, one row per
    chunk, one nonzero digest per data array; every digest differs (keyed by the place)."""
    m = zarr.open_group(stores["root"] / "A")["manifest"]
    rows = np.asarray(m[...])
    assert m.attrs["arrays"] == arrays(stores["root"] / "A")
    assert rows.shape == (4, len(m.attrs["arrays"])) and np.all(rows)
    assert np.unique(rows).size == rows.size
    assert not np.any(rows == np.asarray(zarr.open_group(stores["root"] / "B")["manifest"][...]))


def test_a_refusal_names_the_store_and_the_chunk(stores):
    a = _copy(stores, "A", "names")
    _swap(a, stores["root"] / "B", "x", 0)
    with pytest.raises(StoreError, match=r"names.*damaged.*rows 0:1024 of 'x' \(c/0/0\).*another"):
        resume(a)
    a = _copy(stores, "A", "foreign-slot")
    shutil.rmtree(a / "checkpoints")
    shutil.copytree(stores["root"] / "B" / "checkpoints", a / "checkpoints")
    with pytest.raises(StoreError, match=r"'checkpoints/\d' was written by another store"):
        resume(a)


def test_rows_cut(stores):
    reference = stores["A"]
    # the last chunk of every array deleted; of one array; one chunk cut short
    a = _copy(stores, "A", "cut-all")
    for name in arrays(a):
        chunk(a, name, 3).unlink()
    assert resumed_or_refused(a, reference) == "refused"
    a = _copy(stores, "A", "cut-one")
    chunk(a, "element_v", 2).unlink()
    assert resumed_or_refused(a, reference) == "refused"
    a = _copy(stores, "A", "cut-short")
    raw = chunk(a, "t", 1).read_bytes()
    chunk(a, "t", 1).write_bytes(raw[: len(raw) - 1024])
    assert resumed_or_refused(a, reference) == "refused"
    # the rows of the last chunk past the checkpoint of a stopped store: written again
    a = _copy(stores, "A_stop", "cut-after")
    assert chunk(a, "x", 2).exists()  # rows of the segment it was stopped in
    for name in arrays(a):
        chunk(a, name, 2).unlink(missing_ok=True)
    assert resumed_or_refused(a, reference) == "equal"


def test_checkpoints_rewritten(stores):
    """A checkpoint rewritten with a valid CRC: its step off the grid, at an earlier point
    than its state, or only its CRC recomputed (its seal then fails): refused."""
    for target in ("A", "A_stop"):
        for change in ("step+1", "step-1", "earlier", "crc only", "slot"):
            a = _copy(stores, target, f"{target}-rewritten-{change}")
            cps = slots(a)
            k = max((0, 1), key=lambda i: cps[i].seq)
            c = cps[k]
            if change in ("step+1", "step-1"):
                forged = pack(type(c)(**{**c.__dict__, "step": c.step + int(change[-2:])}))
            elif change == "earlier":  # the state of this point, the rows of the one before
                older = cps[1 - k]
                forged = pack(type(c)(**{**c.__dict__, "step": older.step, "rows": older.rows}))
            elif change == "slot":  # the newest record in the other slot as well
                forged, k = pack(c), 1 - k
            else:
                raw = bytearray(pack(c).tobytes())
                struct.pack_into("<Q", raw, 16, c.step - 1024)  # step, CRC recomputed
                raw[-4:] = struct.pack("<I", zlib.crc32(bytes(raw[:-4])))
                forged = np.frombuffer(bytes(raw), dtype=np.uint8)
            put_slot(a, k, bytes(forged))
            with pytest.raises(StoreError, match=rf"damaged.*'checkpoints/{k}'"):
                resume(a)


def test_reading_refuses_what_resume_refuses(stores):
    """A Solution read after its store was damaged: StoreError naming the chunk, never other
    numbers (the arrays read on access check every chunk they read)."""
    a = _copy(stores, "A", "read")
    sol = resume(a)
    assert equal(content(sol), stores["A"])
    _swap(a, stores["root"] / "B", "x", 1)
    with pytest.raises(StoreError, match=r"rows 1024:2048 of 'x'.*another"):
        np.asarray(sol.x)
    with pytest.raises(StoreError, match=r"rows 2048:3072 of 'x'"):
        sol.x[2500]
    np.testing.assert_array_equal(sol.x[:1000], stores["A"]["x"][:1000])  # chunk 0 intact
    _foreign_chunk(a, stores["root"] / "B", "v", 3)
    with pytest.raises(StoreError, match=r"rows 3072:4001 of 'v'"):
        sol.v[-1]
    raw = bytearray(chunk(a, "a", 0).read_bytes())
    raw[100] ^= 1  # a flipped byte: zarr's CRC-32C, reported as a StoreError too
    chunk(a, "a", 0).write_bytes(bytes(raw))
    with pytest.raises(StoreError, match=r"rows 0:1024 of 'a' \(c/0/0\) is corrupt"):
        sol.a[5]
    # the Solution solve returned reads through the same checks
    b = stores["root"] / "cases" / "fresh"
    shutil.rmtree(b, ignore_errors=True)
    fresh = duhamel.solve(
        system(0.3), duhamel.Semianalytic(), **KW, store=Store(b, segment_bytes=1)
    )
    shutil.copyfile(chunk(stores["root"] / "B", "t", 2), chunk(b, "t", 2))
    np.testing.assert_array_equal(fresh.t[:], stores["A"]["t"])  # the same times: harmless
    shutil.copyfile(chunk(stores["root"] / "B", "x", 2), chunk(b, "x", 2))
    with pytest.raises(StoreError, match=r"rows 2048:3072 of 'x'"):
        fresh.x[:, 1]


def test_damage_campaign(stores):
    """Random damage, composed: chunks moved between the stores and places, checkpoint slots
    exchanged, folders replaced, rows cut; no resumed run differs without a StoreError."""
    rng = np.random.default_rng(38)
    names = arrays(stores["root"] / "A")
    kinds = ["foreign", "swap", "move", "other array", "slot", "folder", "cut", "manifest row"]
    outcomes = {"equal": 0, "refused": 0}
    for case in range(30):
        target = str(rng.choice(["A", "A_stop"]))
        a = _copy(stores, target, f"campaign-{case}")
        others = [stores["root"] / s for s in ("B", "B_stop", "A_stop", "A")]
        for _ in range(int(rng.integers(1, 3))):
            kind = str(rng.choice(kinds))
            b = others[int(rng.integers(len(others)))]
            name, i, j = str(rng.choice(names)), int(rng.integers(3)), int(rng.integers(3))
            if kind == "foreign" and chunk(b, name, i).exists():
                shutil.copyfile(chunk(b, name, i), chunk(a, name, i))
            elif kind in ("swap", "move") and chunk(a, name, i).exists():
                one = chunk(a, name, i).read_bytes()
                if kind == "swap" and chunk(a, name, j).exists():
                    chunk(a, name, i).write_bytes(chunk(a, name, j).read_bytes())
                chunk(a, name, j).write_bytes(one)
            elif kind == "other array" and chunk(a, other := str(rng.choice(names)), i).exists():
                if other == name:
                    continue
                shutil.copyfile(chunk(a, other, i), chunk(a, name, i))
            elif kind == "slot":
                src = zarr.open_group(b)["checkpoints"][str(i % 2)][...]
                put_slot(a, int(rng.integers(2)), bytes(src))
            elif kind == "folder":
                what = str(rng.choice(["data", "checkpoints", "manifest"]))
                shutil.rmtree(a / what)
                shutil.copytree(b / what, a / what)
            elif kind == "cut":
                for n in names[: int(rng.integers(1, len(names) + 1))]:
                    chunk(a, n, 2 + i % 2).unlink(missing_ok=True)
            elif kind == "manifest row":
                shutil.copyfile(
                    b / "manifest" / "c" / str(i) / "0", a / "manifest" / "c" / str(i) / "0"
                )
        outcomes[resumed_or_refused(a, stores["A"])] += 1
    assert outcomes["refused"] > 15 and outcomes["equal"] > 0, outcomes


# -- format 2: the build before, as a legacy format --------------------------------------------


def _format2(path: Path) -> None:
    """Rewrites a format-3 store as the build before wrote it (format 2, written out here
    after its specification, not with the library's code): no identity and no manifest, the
    root checksum over grid, model text and model arrays, checkpoints ``DUHCKPT1`` with their
    energy totals beside them in ``energy_carry``."""
    group = zarr.open_group(path)
    record = dict(group.attrs["duhamel"])
    record.pop("store")
    crc = zlib.crc32(json.dumps(record["grid"], sort_keys=True, allow_nan=True).encode())
    crc = zlib.crc32(record["model"].encode(), crc)
    for name in sorted(group["model"].array_keys()):
        a = np.ascontiguousarray(group["model"][name][...])
        crc = zlib.crc32(f"{name}|{a.dtype.str}|{a.shape}".encode(), crc)
        crc = zlib.crc32(a.tobytes(), crc)
    group.attrs["duhamel"] = {**record, "format": 2, "checksum": crc}
    shutil.rmtree(path / "manifest")
    for k, c in enumerate(slots(path)):
        el_size = 2**64 - 1 if c.element_state is None else c.element_state.size
        head = struct.pack("<8s8Qd2Q", b"DUHCKPT1", c.seq, c.step, c.rows, c.newton_iterations,
                           c.closed_form_steps, c.factorizations, c.subdivided_steps,
                           c.subdivision_depth, c.wall_time, c.state.size, el_size)  # fmt: skip
        body = head + c.state.astype("<f8").tobytes()
        body += b"" if c.element_state is None else c.element_state.astype("<f8").tobytes()
        raw = np.frombuffer(body + struct.pack("<I", zlib.crc32(body)), dtype=np.uint8)
        put_slot(path, k, raw.tobytes())
        carry = group.require_group("energy_carry")
        blob = np.concatenate([[float(c.seq)], c.carry])
        carry.create_array(str(c.seq % 2), shape=blob.shape, dtype="f8", overwrite=True)
        carry[str(c.seq % 2)][...] = blob


def test_format_2_stores_resume_and_read_as_legacy(stores):
    reference = stores["A"]
    for target in ("A", "A_stop"):
        a = _copy(stores, target, f"legacy-{target}")
        _format2(a)
        sol = resume(a)
        assert equal(content(sol), reference)
        # continued in its own format: no identity, no manifest, DUHCKPT1 records
        assert zarr.open_group(a).attrs["duhamel"]["format"] == 2
        assert not (a / "manifest").exists()
        assert all(c is not None and not c.store for c in slots(a))
        assert equal(content(resume(a)), reference)
    # its arrays read through their CRC-32C: a changed byte is a StoreError on access too
    raw = bytearray(chunk(a, "v", 2).read_bytes())
    raw[64] ^= 2
    chunk(a, "v", 2).write_bytes(bytes(raw))
    with pytest.raises(StoreError, match=r"legacy-A_stop.*rows 2048:3072 of 'v' \(c/2/0\)"):
        sol.v[3000]
    # what format 2 can check is checked: a changed byte, a forged checkpoint, a torn slot
    a = _copy(stores, "A_stop", "legacy-flip")
    _format2(a)
    raw = bytearray(chunk(a, "x", 1).read_bytes())
    raw[8] ^= 4
    chunk(a, "x", 1).write_bytes(bytes(raw))
    with pytest.raises(StoreError, match=r"legacy-flip.*damaged.*rows 1024:2048 of 'x'"):
        resume(a)
    a = _copy(stores, "A_stop", "legacy-forged")
    _format2(a)
    cps = slots(a)
    k = max((0, 1), key=lambda i: cps[i].seq)
    raw = bytearray(zarr.open_group(a)["checkpoints"][str(k)][...].tobytes())
    struct.pack_into("<Q", raw, 16, cps[k].step + 1)
    raw[-4:] = struct.pack("<I", zlib.crc32(bytes(raw[:-4])))
    put_slot(a, k, bytes(raw))
    with pytest.raises(StoreError, match=rf"legacy-forged.*'checkpoints/{k}'.*off the run"):
        resume(a)
    a = _copy(stores, "A_stop", "legacy-torn")
    _format2(a)
    put_slot(a, k, bytes(zarr.open_group(a)["checkpoints"][str(k)][...].tobytes()[:-3]) + b"xyz")
    assert equal(content(resume(a)), reference)  # from the older slot
    # a format-3 checkpoint in a format-2 store is not its own
    a = _copy(stores, "A_stop", "legacy-mixed")
    new = zarr.open_group(a)["checkpoints"]["0"][...]
    _format2(a)
    put_slot(a, 0, bytes(new))
    with pytest.raises(StoreError, match=r"'checkpoints/0' is of store format 3"):
        resume(a)
