"""The version of ``rocking``: a leaf, so that what records it (a study's configuration) need not import the package."""

__version__ = "0.1.0"
