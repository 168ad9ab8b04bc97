"""What can stop a fleet run before any unit is analysed. A unit that
fails is never one of these: it is a row of the table with its error."""


class FleetError(Exception):
    """A fleet run that cannot start or finish."""


class FleetInputError(FleetError, ValueError):
    """A manifest, a unit folder or a limits file that cannot be used; the
    message names the file and the line."""


class Interrupted(FleetError):
    """A run stopped by Ctrl-C after writing the table of the units it had
    finished; the same run again analyses only the others."""

    def __init__(self, table, counts):
        self.table, self.counts = table, counts
        left = counts["units"] - counts["finished"]
        super().__init__(f"interrupted: {counts['finished']} of the manifest's {counts['units']} "
                         f"units are done and kept in {table} ({counts['analysed']} analysed in "
                         f"this run); run the same command again to analyse the other {left}")
