"""``python -m laserpeople.cli``: the same as the ``laserpeople`` command."""

from laserpeople.cli import run

if __name__ == "__main__":
    run()
