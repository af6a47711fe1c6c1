"""The toolkit's version, from the installed package's metadata (pyproject.toml), defined once:
`tensegrity.__version__` and every file's `source` attribute read it from here."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("tensegrity")
except PackageNotFoundError:  # run from a source tree that was never installed
    __version__ = "0+unknown"
