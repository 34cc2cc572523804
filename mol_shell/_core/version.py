"""The package's version, in a module of its own so that modules record it without importing the package."""

__version__ = "0.6.0.dev1"
