"""``python -m laserpeople.cli``: the same as the ``laserpeople`` command."""

from laserpeople.cli import main

if __name__ == "__main__":
    main()
