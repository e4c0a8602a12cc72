"""SymPy derivation of rocking-block models and generation of their code.

``derive`` knows nothing of the runtime: it reads a model spec, derives the
equations from energies and writes NumPy, C, LaTeX and a manifest into a folder.
Its command line is ``python -m rocking.derive``, :func:`rocking.derive.cli.main`.
"""
