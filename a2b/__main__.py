"""``python -m a2b``: the same command line as the ``a2b`` script."""

from .cli import cli

if __name__ == "__main__":
    cli(prog_name="a2b")
