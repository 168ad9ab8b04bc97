"""What can stop a fleet run before any unit is analysed. A unit that
fails is never one of these: it is a row of the table with its error."""


class FleetError(Exception):
    """A fleet run that cannot start or finish."""


class FleetInputError(FleetError, ValueError):
    """A manifest, a unit folder or a limits file that cannot be used; the
    message names the file and the line."""
