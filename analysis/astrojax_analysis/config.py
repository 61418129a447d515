"""A run's or sweep's stored configuration read back: /config's TOML text and its --set
overrides (reader.read_config), as values."""
import tomllib

from .errors import SweepFileError


def model_values(path, run, defaults):
    """[model] values of a run (read_run's dict): its stored configuration, then its --set
    overrides, else `defaults`."""
    try:
        model = tomllib.loads(run["config"]).get("model", {})
    except tomllib.TOMLDecodeError as e:
        raise SweepFileError(path, "/config", f"not TOML: {e}") from None
    out = {k: model.get(k, v) for k, v in defaults.items()}
    for item in run["overrides"]:
        key, _, value = item.strip().partition("=")
        name = key.strip().removeprefix("model.")
        if key.strip().startswith("model.") and name in out:
            out[name] = value
    try:
        return {k: float(v) for k, v in out.items()}
    except (TypeError, ValueError):
        raise SweepFileError(path, "/config", f"a model value of {sorted(out)} is not a number") from None
