"""The one exception type for mistakes a user can fix (a bad campaign file, a missing scene): the command
line prints its message alone, without a traceback."""


class CampaignError(Exception):
    """A user error; the message names the file, key and (where known) line."""
