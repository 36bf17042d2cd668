"""Type stubs of the native module (src/lib.rs); the public API is the package's
(rotorid/__init__.py), which wraps these calls."""

from typing import List, Optional, Sequence, Tuple, Union

KINDS: List[str]
FLOATS_PER_SAMPLE: int

class RotoridError(Exception):
    kind: str

class InputError(RotoridError): ...
class LogError(RotoridError): ...
class IdentifyError(RotoridError): ...
class SimulateError(RotoridError): ...
class CoreError(RotoridError): ...
class NonFiniteError(CoreError): ...
class OutOfRangeError(CoreError): ...
class TimeStepError(CoreError): ...
class NonMonotonicTimeError(CoreError): ...
class ConfigError(CoreError): ...
class IncompatibleError(CoreError): ...
class NumericalError(CoreError): ...

class Identifier:
    def __new__(
        cls,
        kind: str,
        premises: Optional[Sequence[Tuple[str, Sequence[float], Sequence[float]]]] = None,
    ) -> "Identifier": ...
    @property
    def kind(self) -> str: ...
    @property
    def kind_code(self) -> int: ...
    @property
    def export_size(self) -> int: ...
    def step(
        self,
        time_us: int,
        attitude: Sequence[float],
        velocity: Sequence[float],
        rates: Sequence[float],
        controls: Sequence[float],
    ) -> Tuple[List[float], Optional[List[float]]]:
        """One sample: time (µs), attitude [φ θ ψ] (rad), velocity [v_x v_y v_z] (m/s,
        paper axes), rates [q r p] (deg/s), controls [col ped lon lat]. Returns the one-step
        prediction [v_x v_y v_z q r p] and the innovation (None at a chain's start)."""
    def resume(
        self,
        time_us: int,
        attitude: Sequence[float],
        velocity: Sequence[float],
        rates: Sequence[float],
        controls: Sequence[float],
    ) -> List[float]: ...
    def compensate(
        self,
        gyro_noise: Sequence[float],
        how: Union[None, str, Sequence[str]] = None,
    ) -> Tuple[int, int]:
        """Removes the gyro noise σ [q r p] (deg/s) from the rate models' parameters
        ("damping" or "full", per rate or for all); returns (compensated, refused) rules."""
    def reset(self) -> None: ...
    def _step_block(self, times: bytes, floats: bytes) -> Tuple[bytes, bytes]: ...
    def export(self) -> bytes:
        """The C interface's export bytes (ROTORID_<KIND>_EXPORT_SIZE long)."""
    def import_(self, data: bytes) -> None: ...

def log_columns() -> List[str]: ...
def read_log(
    path: str, rate: Optional[float] = None, from_s: Optional[float] = None, to_s: Optional[float] = None
) -> Tuple[bytes, str]: ...
def hover_block(block: bytes) -> Tuple[bytes, bytes]: ...
def identify(
    train: List[str],
    verify: Optional[str] = None,
    holdout: float = 0.3,
    rate: Optional[float] = None,
    from_s: Optional[float] = None,
    to_s: Optional[float] = None,
    out: Optional[str] = None,
    window: float = 2.0,
    plots: bool = True,
    warm_start: Optional[str] = None,
    gyro_noise: str = "auto",
    free_run_velocity: str = "model",
    observer_gain: str = "auto",
) -> Tuple[str, str, str, List[str]]: ...
def simulate(
    kind: str,
    seed: int = 1,
    plant: str = "xcell60",
    plant_variation: Optional[int] = None,
    duration: Optional[float] = None,
    clean: bool = False,
    noise_scale: float = 1.0,
    cyclic_power: float = 1.0,
    out: Optional[str] = None,
) -> Optional[bytes]: ...
