"""motiontool: lint, transform and simulate Webots ``.motion`` files."""

__version__ = "0.1.0"
__all__ = ["__version__"]
