"""Hostile NetCDF-4 files for the tests and the bench: datasets added with the HDF5 library that the NetCDF library
loads (through ctypes; the NetCDF library cannot make them): one stored in an external file, one virtual; and a
global heap damaged so that the HDF5 library loops forever."""

from __future__ import annotations

import ctypes
import os
from pathlib import Path

from rocking.study.files import hdf5_library
from rocking.study.hdf5_walk import load

#: H5F_ACC_RDWR, H5F_UNLIMITED (the size of an external file without end).
RDWR, UNLIMITED = 1, ctypes.c_uint64(-1).value


def _lib() -> ctypes.CDLL:
    lib = load(hdf5_library())
    hid, size = ctypes.c_int64, ctypes.c_uint64
    for name, restype, argtypes in (
        ("H5open", ctypes.c_int, []),
        ("H5Pcreate", hid, [hid]),
        ("H5Pset_external", ctypes.c_int, [hid, ctypes.c_char_p, ctypes.c_int64, size]),
        ("H5Pset_virtual", ctypes.c_int, [hid, hid, ctypes.c_char_p, ctypes.c_char_p, hid]),
        ("H5Screate_simple", hid, [ctypes.c_int, ctypes.POINTER(size), ctypes.POINTER(size)]),
        ("H5Sclose", ctypes.c_int, [hid]),
        ("H5Dcreate2", hid, [hid, ctypes.c_char_p, hid, hid, hid, hid, hid]),
        ("H5Dclose", ctypes.c_int, [hid]),
        ("H5Ldelete", ctypes.c_int, [hid, ctypes.c_char_p, hid]),
    ):
        function = getattr(lib, name)
        function.restype, function.argtypes = restype, argtypes
    lib.H5open()
    return lib


def _global(lib: ctypes.CDLL, name: str) -> int:
    return ctypes.c_int64.in_dll(lib, name).value


def add_dataset(
    path: Path, name: str, n: int, external: str | None = None, virtual: tuple | None = None, replace: bool = False
) -> None:
    """Add to the HDF5 file ``path`` a dataset ``name`` of ``n`` doubles, never written, stored in the file, or in
    the ``external`` file (from its start, without end), or virtual: the dataset ``virtual[1]`` of the file
    ``virtual[0]``; ``replace``: in place of the dataset of that name."""
    lib = _lib()
    file = lib.H5Fopen(os.fsencode(path), RDWR, 0)
    assert file >= 0, path
    if replace:
        assert lib.H5Ldelete(file, name.encode(), 0) >= 0, name
    dims = (ctypes.c_uint64 * 1)(n)
    space = lib.H5Screate_simple(1, dims, None)
    dcpl = lib.H5Pcreate(_global(lib, "H5P_CLS_DATASET_CREATE_ID_g"))
    try:
        if external is not None:
            assert lib.H5Pset_external(dcpl, os.fsencode(external), 0, UNLIMITED) >= 0
        if virtual is not None:
            source = lib.H5Screate_simple(1, dims, None)
            assert lib.H5Pset_virtual(dcpl, space, os.fsencode(virtual[0]), virtual[1].encode(), source) >= 0
            lib.H5Sclose(source)
        dset = lib.H5Dcreate2(file, name.encode(), _global(lib, "H5T_NATIVE_DOUBLE_g"), space, 0, dcpl, 0)
        assert dset >= 0, name
        lib.H5Dclose(dset)
    finally:
        lib.H5Pclose(dcpl)
        lib.H5Sclose(space)
        lib.H5Fclose(file)


def zero_global_heap(nc: Path) -> None:
    """Zero 530 bytes of the first global heap of ``nc`` (its strings): the HDF5 library, hence the NetCDF library,
    then loops forever opening a dataset (found by bench/damaged_nc.py, copy 71 of seed 36)."""
    data = bytearray(nc.read_bytes())
    at = data.index(b"GCOL") + 384
    data[at : at + 530] = bytes(530)
    nc.write_bytes(bytes(data))
