"""`python -m rcl` is the `rcl` command."""
from .launch import main

main()
