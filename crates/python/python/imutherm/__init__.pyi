from typing import Any, Literal, Sequence, TypedDict, Union

import numpy as np
import numpy.typing as npt

from . import allantools as allantools

class ImuthermError(ValueError): ...

STATISTICS: tuple[str, ...]

Taus = Union[Literal["octave", "decade", "all", "many"], Sequence[float], npt.NDArray[np.floating]]
DataType = Literal["freq", "phase"]
Samples = npt.ArrayLike

class Curve:
    taus: npt.NDArray[np.float64]
    devs: npt.NDArray[np.float64]
    lo: npt.NDArray[np.float64]
    hi: npt.NDArray[np.float64]
    edf: npt.NDArray[np.float64]
    n: npt.NDArray[np.uint64]
    alpha: npt.NDArray[np.int32]
    noise_id: npt.NDArray[np.str_]
    m: npt.NDArray[np.uint64]
    stat: str
    data_type: str
    rate: float
    confidence: float
    samples: int
    nan_samples: int
    def __len__(self) -> int: ...
    def to_pandas(self) -> Any: ...

def analyze(
    stat: str,
    y: Samples,
    rate: float = 1.0,
    taus: Taus = "octave",
    data_type: DataType = "freq",
    confidence: float = 0.683,
) -> Curve: ...
def adev(y: Samples, rate: float = 1.0, taus: Taus = "octave", data_type: DataType = "freq", confidence: float = 0.683) -> Curve: ...
def oadev(y: Samples, rate: float = 1.0, taus: Taus = "octave", data_type: DataType = "freq", confidence: float = 0.683) -> Curve: ...
def mdev(y: Samples, rate: float = 1.0, taus: Taus = "octave", data_type: DataType = "freq", confidence: float = 0.683) -> Curve: ...
def tdev(y: Samples, rate: float = 1.0, taus: Taus = "octave", data_type: DataType = "freq", confidence: float = 0.683) -> Curve: ...
def hdev(y: Samples, rate: float = 1.0, taus: Taus = "octave", data_type: DataType = "freq", confidence: float = 0.683) -> Curve: ...
def ohdev(y: Samples, rate: float = 1.0, taus: Taus = "octave", data_type: DataType = "freq", confidence: float = 0.683) -> Curve: ...
def totdev(y: Samples, rate: float = 1.0, taus: Taus = "octave", data_type: DataType = "freq", confidence: float = 0.683) -> Curve: ...
def mtotdev(y: Samples, rate: float = 1.0, taus: Taus = "octave", data_type: DataType = "freq", confidence: float = 0.683) -> Curve: ...
def ttotdev(y: Samples, rate: float = 1.0, taus: Taus = "octave", data_type: DataType = "freq", confidence: float = 0.683) -> Curve: ...
def htotdev(y: Samples, rate: float = 1.0, taus: Taus = "octave", data_type: DataType = "freq", confidence: float = 0.683) -> Curve: ...
def theo1(y: Samples, rate: float = 1.0, taus: Taus = "octave", data_type: DataType = "freq", confidence: float = 0.683) -> Curve: ...

class TermEstimate(TypedDict, total=False):
    value: float | None
    lo: float
    hi: float
    reason: str

class TermReading(TypedDict):
    symbol: str
    slope: TermEstimate
    fit: TermEstimate
    value: float | None
    how: Literal["fit", "slope", "upper_bound", "none"]
    note: str | None

class NoiseTerms(TypedDict):
    curve: dict[str, Any]
    terms: dict[str, TermReading]

def noise_terms(y: Samples, rate: float = 1.0, confidence: float = 0.95) -> NoiseTerms: ...
