"""The package's version (``jointgap.__version__``), in a module of its own so that the
modules that print or compare it need not import the package's namespace."""

__version__ = "0.1.0"
