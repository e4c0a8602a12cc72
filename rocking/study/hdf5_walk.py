"""The check of an HDF5 (NetCDF-4) file's storage from its metadata, run in a process of its own.

:func:`rocking.study.files.check_hdf5` runs this file as ``python -I -S hdf5_walk.py LIBRARY FILE`` with a time
limit: the HDF5 library loops forever on some damaged metadata (an object header whose bytes were zeroed: the
NetCDF library does too) and may crash on others; in a process of its own, that is a refusal in one line. The
process imports the standard library only (it starts in milliseconds) and prints one JSON line: ``{"ok": true}`` or
``{"refused": reason}``.
"""

from __future__ import annotations

import ctypes
import json
import os
import sys

#: Most links an HDF5 file of a study may hold (its variables, and the datasets of dimensions without one).
MAX_LINKS = 1000

#: HDF5's constants (H5Fpublic.h, H5Ipublic.h, H5Lpublic.h, H5Dpublic.h; the same from 1.10 to 2.0).
H5P_DEFAULT, H5F_ACC_RDONLY, H5_INDEX_NAME, H5_ITER_INC, H5L_TYPE_HARD, H5I_DATASET = 0, 0, 0, 0, 0, 5
#: The storage of a dataset that holds its own bytes in the file (H5D_layout_t): not virtual (other files').
LAYOUTS = {0: "compact", 1: "contiguous", 2: "chunked"}
H5D_VIRTUAL = 3

#: ``herr_t (*)(hid_t group, const char *name, const H5L_info2_t *info, void *data)``: H5Lvisit2's callback.
VISIT = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_int64, ctypes.c_char_p, ctypes.c_void_p, ctypes.c_void_p)


def load(path: str) -> ctypes.CDLL:
    """The HDF5 library at ``path``, the functions used typed (``hid_t`` is 64 bits since HDF5 1.10)."""
    lib = ctypes.CDLL(path)
    hid, text = ctypes.c_int64, ctypes.c_char_p
    for name, restype, argtypes in (
        ("H5Eset_auto2", ctypes.c_int, [hid, ctypes.c_void_p, ctypes.c_void_p]),
        ("H5Fopen", hid, [text, ctypes.c_uint, hid]),
        ("H5Fclose", ctypes.c_int, [hid]),
        ("H5Lvisit2", ctypes.c_int, [hid, ctypes.c_int, ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p]),
        ("H5Oopen", hid, [hid, text, hid]),
        ("H5Oclose", ctypes.c_int, [hid]),
        ("H5Iget_type", ctypes.c_int, [hid]),
        ("H5Dget_create_plist", hid, [hid]),
        ("H5Pget_layout", ctypes.c_int, [hid]),
        ("H5Pget_external_count", ctypes.c_int, [hid]),
        ("H5Pget_nfilters", ctypes.c_int, [hid]),
        ("H5Pclose", ctypes.c_int, [hid]),
    ):
        function = getattr(lib, name)
        function.restype, function.argtypes = restype, argtypes
    lib.H5Eset_auto2(0, None, None)  # H5E_DEFAULT: no error stack printed on stderr, the reason is ours
    return lib


def name_of(name: str) -> str:
    """A name read from a file, as a one-line message shows it."""
    return name if name.isprintable() and len(name) <= 40 else repr(name[:40]) + ("..." if len(name) > 40 else "")


def links(lib: ctypes.CDLL, file: int) -> list[tuple[str, int]]:
    """Every link of an open HDF5 file, depth first from its root: ``(path, link type)``, at most
    :data:`MAX_LINKS` + 1."""
    found: list[tuple[str, int]] = []

    def visit(group, name, info, data) -> int:
        # H5L_info2_t starts with its H5L_type_t (an int): hard, soft or external.
        found.append((name.decode("utf-8", "replace"), ctypes.c_int.from_address(info).value))
        return 1 if len(found) > MAX_LINKS else 0  # > 0 stops the visit

    if lib.H5Lvisit2(file, H5_INDEX_NAME, H5_ITER_INC, VISIT(visit), None) < 0:
        raise ValueError("its HDF5 links cannot be read")
    return found


def dataset_storage(lib: ctypes.CDLL, file: int, name: str) -> None:
    """Refuse the object ``name`` of an open HDF5 file unless it is a dataset that keeps its bytes in the file,
    unfiltered: not a group, not virtual (other datasets' bytes), not in external files, no filter (a filter
    may be a plugin the file would choose)."""
    obj = lib.H5Oopen(file, name.encode(), H5P_DEFAULT)
    if obj < 0:
        raise ValueError(f"its object {name_of(name)} cannot be opened")
    try:
        if lib.H5Iget_type(obj) != H5I_DATASET:
            raise ValueError(f"{name_of(name)} is not a dataset (a study's file holds datasets only, no groups)")
        plist = lib.H5Dget_create_plist(obj)
        if plist < 0:
            raise ValueError(f"dataset {name_of(name)}: its storage cannot be read")
        try:
            layout, external = lib.H5Pget_layout(plist), lib.H5Pget_external_count(plist)
            filters = lib.H5Pget_nfilters(plist)
        finally:
            lib.H5Pclose(plist)
    finally:
        lib.H5Oclose(obj)
    if layout not in LAYOUTS:
        raise ValueError(
            f"dataset {name_of(name)} is {'virtual' if layout == H5D_VIRTUAL else 'of an unknown storage'}"
        )
    if external != 0:
        raise ValueError(f"dataset {name_of(name)} is stored in {external} external file(s), not in the file")
    if filters != 0:
        raise ValueError(f"dataset {name_of(name)} is filtered ({filters} filter(s)); a study's data are stored plain")


def check(lib: ctypes.CDLL, path: str) -> None:
    """Refuse the HDF5 file ``path`` unless every link is a hard link to a dataset that keeps its own bytes in the
    file, unfiltered (:func:`dataset_storage`); no groups, soft or external links; at most :data:`MAX_LINKS`.

    Raises
    ------
    ValueError
        With the reason.
    """
    file = lib.H5Fopen(os.fsencode(path), H5F_ACC_RDONLY, H5P_DEFAULT)
    if file < 0:
        raise ValueError("the HDF5 library cannot open it")
    try:
        found = links(lib, file)
        if len(found) > MAX_LINKS:
            raise ValueError(f"more than {MAX_LINKS} HDF5 objects")
        for name, kind in found:
            if kind != H5L_TYPE_HARD:
                raise ValueError(f"{name_of(name)} is a soft or external link (a study's file holds its own data)")
            dataset_storage(lib, file, name)
    finally:
        lib.H5Fclose(file)


def main(argv: list[str]) -> int:
    """``hdf5_walk.py LIBRARY FILE``: one JSON line, ``{"ok": true}`` or ``{"refused": reason}``."""
    library, path = argv
    try:
        check(load(library), path)
        answer: dict = {"ok": True}
    except ValueError as exc:
        answer = {"refused": str(exc)}
    print(json.dumps(answer), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
