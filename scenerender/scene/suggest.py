"""'Did you mean' hints for typos in keys, names and choices."""
from __future__ import annotations

import difflib


def did_you_mean(word: str, candidates) -> str:
    """' (did you mean 'x'?)' for the closest candidate, or '' when nothing is close."""
    match = difflib.get_close_matches(word, list(candidates), n=1, cutoff=0.6)
    if not match and candidates:
        lowered = {c.lower(): c for c in candidates}
        if word.lower() in lowered:
            match = [lowered[word.lower()]]
    return f" (did you mean '{match[0]}'?)" if match else ""
