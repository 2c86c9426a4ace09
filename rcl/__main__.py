"""`python -m rcl` is the `rcl` command."""
from .cli import entry

entry()
