"""Python client of the compaction-sweep service (docs/python.md)."""
from .client import POINT_COLUMNS, RESULT_COLUMNS, ApiError, Client, linear_axis, log_axis
from .npy import NpyError

__version__ = "0.1.0"
__all__ = ["ApiError", "Client", "NpyError", "POINT_COLUMNS", "RESULT_COLUMNS", "linear_axis",
           "log_axis"]
