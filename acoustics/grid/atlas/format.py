"""What an atlas store is on disk: one Zarr (format 3) store, one chunk per table slab.

docs/formats.md "Atlas (Zarr store)". Dimensions ``month, origin, class, band, bearing, depth,
range``; ``tl_db(month, origin, class, band, bearing, depth, range)`` float32 and ``k_db(month,
origin, class, band, bearing, range)`` float64 have one chunk per (month, origin) table;
``bottom_depth_m(origin, bearing, range)`` one per origin; ``done(month, origin)`` and
``table_hash(month, origin)`` one per table. Every chunk ends with a CRC-32C checksum (Zarr's
``crc32c`` codec), so a damaged chunk fails to decode instead of being read as numbers; a
missing one is found by its key. ``class`` and ``band`` are integer coordinates with the names
in their ``labels`` attribute (Zarr 3 has no stable string type). The store is written from a
template (metadata and the small variables; xarray ``to_zarr(compute=False)``), then each
table by whichever process computed it, with a region write aligned to its chunks (one writer
per chunk: unaligned parallel region writes lose data silently, xarray issues 8371 and 10501),
then its ``done`` flag and hash. The builder (``acoustics.builder.atlas``) asks this module for
the template (`store_template`) and writes through it; the reader is ``acoustics.grid.atlas.store``.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import numpy as np
import xarray as xr

from acoustics.errors import GridFileError
from acoustics.grid.dataset import grid_attrs, grid_coords
from acoustics.grid.formats import ATLAS_FORMAT
from acoustics.urick import urick_tables

#: The kind attribute every atlas store carries beside ``tmakit_format``.
ATLAS_KIND = "atlas"
TABLE_DIMS = ("month", "origin")
TL_DIMS = ("month", "origin", "class", "band", "bearing", "depth", "range")
K_DIMS = ("month", "origin", "class", "band", "bearing", "range")
BOTTOM_DIMS = ("origin", "bearing", "range")
#: The variables written per table (the bottom by the table of the first month).
TABLE_VARS = ("tl_db", "k_db")


class AtlasFileError(GridFileError):
    """An atlas store that is missing, not tmakit's, of another format or area, or damaged."""


def _codecs():
    from zarr.codecs import Crc32cCodec, ZstdCodec

    return [ZstdCodec(level=3), Crc32cCodec()]


def table_hash_u64(digest: str) -> int:
    """The first 64 bits of a table's sha256 (hex), as stored in ``table_hash``."""
    return int(digest[:16], 16)


def store_template(area, *, months, lat_deg: np.ndarray, lon_deg: np.ndarray, row_col: np.ndarray,
                   bearing_deg: np.ndarray, depth_m: np.ndarray, range_m: np.ndarray, model: str, digest: str,
                   exe_info: dict | None, left_out, inputs, ray_step_m: float) -> xr.Dataset:
    """The store's template for an atlas of ``area``: coordinates, the small variables and the
    attributes, the tables lazy (`template_dataset`; `write_template` writes it).

    Parameters
    ----------
    area : Area
        The area with its ``[atlas]``.
    months : sequence of int
    lat_deg, lon_deg : ndarray, shape (O,)
        The positions kept, deg.
    row_col : ndarray, shape (O, 2)
        Their lattice row and column (-1 for listed positions).
    bearing_deg, depth_m, range_m : ndarray
        The tables' axes.
    model, digest, exe_info
        The model, the atlas's hash and the BELLHOP executable (``grid_attrs``).
    left_out : sequence of LeftOut
        Positions without a table, and why.
    inputs : sequence of dict
        Each month's data files' digests.
    ray_step_m : float
        BELLHOP's ray step, m.
    """
    base = grid_coords(area, depth_m, range_m)
    coords = {
        "month": ("month", np.asarray(months, dtype=np.int64),
                  {"long_name": "month of the climatology (0: the data files' own)"}),
        "origin": ("origin", np.arange(lat_deg.size, dtype=np.int64), {"long_name": "observer position index"}),
        "origin_lat_deg": ("origin", lat_deg, {"units": "degree_north", "standard_name": "latitude",
                                              "long_name": "observer position, WGS84"}),
        "origin_lon_deg": ("origin", lon_deg, {"units": "degree_east", "standard_name": "longitude",
                                              "long_name": "observer position, WGS84"}),
        "origin_row": ("origin", row_col[:, 0], {"long_name": "lattice row, south first (-1: listed)"}),
        "origin_col": ("origin", row_col[:, 1], {"long_name": "lattice column, west first (-1: listed)"}),
        "class": ("class", np.arange(len(area.classes), dtype=np.int64),
                  {"long_name": "target class hypothesis", "labels": json.dumps([c.name for c in area.classes])}),
        "band": ("band", np.arange(len(area.bands), dtype=np.int64),
                 {"long_name": "frequency band", "labels": json.dumps([b.name for b in area.bands])}),
        "bearing": ("bearing", bearing_deg, {"units": "degree", "long_name": "bearing from the observer, "
                                                                             "clockwise from true north"}),
        "depth": ("depth", depth_m, {"units": "m", "standard_name": "depth", "positive": "down", "axis": "Z",
                                     "long_name": "depth of the point the observer looks at"}),
        "range": ("range", range_m, {"units": "m", "long_name": "range from the observer along the radial"}),
    }
    for name in ("band_low_hz", "band_high_hz", "band_center_hz", "source_depth_m"):
        coords[name] = base[name]
    k_urick, beta = urick_tables(area, range_m)
    small = {
        "k_urick_db": (("class", "band", "range"), k_urick,
                       {"units": "dB", "long_name": "transfer characteristic K(r), Urick approximate formula",
                        "reference": "Grinenkov & Mashoshin eq. 13 with A = 1"}),
        "beta_db_per_km": (("band",), beta, {"units": "dB km-1",
                                             "long_name": "volume attenuation at the band centre"}),
    }
    attrs = grid_attrs(area, model, digest, exe_info, water_depth_m=float(depth_m[-1]), ssp_interpolation="Q")
    own_axis = area.atlas.depth_m is None and area.atlas.depth_step_m is None
    attrs.update({
        "tmakit_format": ATLAS_FORMAT, "tmakit_kind": ATLAS_KIND,
        "title": f"tmakit atlas of bearing-dependent propagation tables for area {area.name}",
        "history": attrs["created"] + " created by tmakit atlas build",
        "ray_step_m": float(ray_step_m),
        "left_out": json.dumps([{"lat_deg": p.lat_deg, "lon_deg": p.lon_deg, "reason": p.reason} for p in left_out]),
        "input_files": json.dumps({str(m): inp for m, inp in zip(months, inputs)}, sort_keys=True),
        "depth_axis": "grid" if own_axis else "atlas",
    })
    if area.atlas.is_lattice:
        dlat, dlon = area.atlas.step_deg
        rows, cols = area.atlas.lattice_shape
        attrs["lattice"] = json.dumps({"lat0_deg": area.atlas.lat_deg[0], "lon0_deg": area.atlas.lon_deg[0],
                                       "dlat_deg": dlat, "dlon_deg": dlon, "rows": rows, "cols": cols})
    sizes = {"month": len(months), "origin": lat_deg.size, "class": len(area.classes), "band": len(area.bands),
             "bearing": bearing_deg.size, "depth": depth_m.size, "range": range_m.size}
    return template_dataset(sizes, coords, small, attrs)


def template_dataset(sizes: dict[str, int], coords: dict, small_vars: dict, attrs: dict) -> xr.Dataset:
    """The atlas's dataset with lazy (dask) tables: written as metadata only by `write_template`."""
    import dask.array as da

    def lazy(dims, dtype, fill, per_table):
        shape = tuple(sizes[d] for d in dims)
        chunks = tuple(1 if d in per_table else sizes[d] for d in dims)
        return da.full(shape, fill, chunks=chunks, dtype=dtype)

    data_vars = dict(small_vars)
    data_vars["tl_db"] = (TL_DIMS, lazy(TL_DIMS, "float32", np.nan, TABLE_DIMS), {
        "units": "dB", "long_name": "band transmission loss between the observer and a point at depth",
        "reference": "1 m from the source", "fixed_end": "observer"})
    data_vars["k_db"] = (K_DIMS, lazy(K_DIMS, "float64", np.nan, TABLE_DIMS), {
        "units": "dB", "long_name": "transfer characteristic K(r) of a target of the class along the bearing",
        "reference": "band level W = P0 + K(r) + H (Grinenkov & Mashoshin eq. 12)"})
    data_vars["bottom_depth_m"] = (BOTTOM_DIMS, lazy(BOTTOM_DIMS, "float64", np.nan, ("origin",)), {
        "units": "m", "long_name": "water depth along the radial", "positive": "down"})
    data_vars["done"] = (TABLE_DIMS, lazy(TABLE_DIMS, "uint8", 0, TABLE_DIMS), {
        "long_name": "1 where the table of (month, origin) is complete", "flag_values": [0, 1]})
    data_vars["table_hash"] = (TABLE_DIMS, lazy(TABLE_DIMS, "uint64", 0, TABLE_DIMS), {
        "long_name": "first 64 bits of the sha256 of the table's inputs"})
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def write_template(path: str | os.PathLike, ds: xr.Dataset) -> None:
    """Write the store's metadata, coordinates and small variables (the tables stay empty)."""
    path = Path(path)
    if path.exists():
        remove_store(path)
    encoding = {name: {"compressors": _codecs()} for name in ds.data_vars}
    for name in ("done", "table_hash"):
        encoding[name]["fill_value"] = 0
    ds.to_zarr(path, mode="w-", compute=False, encoding=encoding, zarr_format=3, consolidated=False)


def remove_store(path: str | os.PathLike) -> None:
    """Remove a store (a folder) or a file in its place."""
    path = Path(path)
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path)
    elif path.exists() or path.is_symlink():
        path.unlink()


def _region(m: int, o: int) -> dict:
    return {"month": slice(m, m + 1), "origin": slice(o, o + 1)}


def write_table(path: str | os.PathLike, m: int, o: int, tl_db: np.ndarray, k_db: np.ndarray,
                bottom_depth_m: np.ndarray | None) -> None:
    """Write the table of (month index m, origin index o): its chunks, and none other.

    ``tl_db`` (class, band, bearing, depth, range), ``k_db`` (class, band, bearing, range);
    ``bottom_depth_m`` (bearing, range) for the table of the first month, None for the others.
    A table is one chunk of each array (``TABLE_DIMS``), so Zarr's own write of the element
    (m, o) is the aligned region write (xarray's region write opens the store and lists its
    members again for each call, about 40 ms a table).
    """
    import zarr

    group = zarr.open_group(str(path), mode="r+", zarr_format=3)
    group["tl_db"][m, o] = np.asarray(tl_db, dtype=np.float32)
    group["k_db"][m, o] = np.asarray(k_db, dtype=np.float64)
    if bottom_depth_m is not None:
        group["bottom_depth_m"][o] = np.asarray(bottom_depth_m, dtype=np.float64)


def set_done(path: str | os.PathLike, m: int, o: int, table_hash: int) -> None:
    """Mark a table complete, with the hash of its inputs (after `write_table`).

    Each flag is its own one-element chunk, so Zarr's own element write is the aligned region
    write here (xarray's costs 40 ms of opening the store for two numbers).
    """
    import zarr

    group = zarr.open_group(str(path), mode="r+", zarr_format=3)
    group["table_hash"][m, o] = np.uint64(table_hash)
    group["done"][m, o] = 1


def clear_done(path: str | os.PathLike, pairs) -> None:
    """Mark tables incomplete before they are recomputed (by the one process that plans)."""
    import zarr

    group = zarr.open_group(str(path), mode="r+", zarr_format=3)
    for m, o in pairs:
        group["done"][m, o] = 0
        group["table_hash"][m, o] = 0


def read_attrs(path: str | os.PathLike) -> dict | None:
    """The store's global attributes, or None when ``path`` is not a Zarr 3 group."""
    meta = Path(path) / "zarr.json"
    try:
        doc = json.loads(meta.read_text(encoding="utf-8"))
    except (OSError, ValueError, UnicodeDecodeError):
        return None
    if not isinstance(doc, dict) or doc.get("node_type") != "group" or doc.get("zarr_format") != 3:
        return None
    attrs = doc.get("attributes", {})
    return attrs if isinstance(attrs, dict) else None


def is_atlas_store(path: str | os.PathLike) -> bool:
    """Whether ``path`` is a store tmakit wrote as an atlas (any format)."""
    return is_atlas_attrs(read_attrs(path))


def is_atlas_attrs(attrs: dict | None) -> bool:
    """Whether a store's attributes (`read_attrs`) are those of a tmakit atlas (any format)."""
    return attrs is not None and attrs.get("tmakit_kind") == ATLAS_KIND and "tmakit_format" in attrs


def check_format(path: str | os.PathLike, attrs: dict) -> None:
    """Refuse a store of another format, naming it and this version's."""
    fmt = attrs.get("tmakit_format")
    if isinstance(fmt, bool) or not isinstance(fmt, int):
        raise AtlasFileError(f"{path}: global attribute tmakit_format must be an integer, got {fmt!r:.40}")
    if fmt != ATLAS_FORMAT:
        newer = " (written by a newer tmakit)" if fmt > ATLAS_FORMAT else ""
        raise AtlasFileError(f"{path}: an atlas of tmakit format {fmt}{newer}; this version reads format "
                             f"{ATLAS_FORMAT}; build it anew with tmakit atlas build "
                             f"{attrs.get('area', 'AREA')}")


def chunk_exists(path: Path, array, index: tuple[int, ...]) -> bool:
    """Whether the chunk at ``index`` (chunk coordinates) is in the store (a local folder)."""
    return (path / array.path / array.metadata.encode_chunk_key(index)).is_file()


def table_chunks(group, m: int, o: int, with_bottom: bool):
    """(array, chunk index) of every chunk a table owns."""
    out = [(group["tl_db"], (m, o, 0, 0, 0, 0, 0)), (group["k_db"], (m, o, 0, 0, 0, 0))]
    if with_bottom:
        out.append((group["bottom_depth_m"], (o, 0, 0)))
    return out


def table_readable(path: Path, group, m: int, o: int, with_bottom: bool) -> bool:
    """Whether every chunk of a table is there and decodes (its checksum holds)."""
    for array, index in table_chunks(group, m, o, with_bottom):
        if not chunk_exists(path, array, index):
            return False
        lead = 1 if array.path.endswith("bottom_depth_m") else 2  # the table's own axes
        selection = tuple(slice(i, i + 1) for i in index[:lead]) + (slice(None),) * (len(index) - lead)
        try:
            array[selection]
        except Exception:  # noqa: BLE001 - zarr and numcodecs raise many kinds for a damaged chunk
            return False
    return True
