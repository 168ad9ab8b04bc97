import os
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

class Channel:
    name: str
    source: str
    quantity: str
    unit: str
    unit_source: str
    data: npt.NDArray[np.float64]

class Problem(TypedDict):
    kind: str
    line: int | None
    column: int | None
    channel: str | None
    count: int
    message: str

class Recording:
    channels: dict[str, npt.NDArray[np.float64]]
    rate: float | None
    rate_source: str
    timestamps: npt.NDArray[np.float64] | None
    metadata: dict[str, Any]
    file: str | None
    format: str
    lines: int | None
    notes: list[str]
    problems: list[Problem]
    problems_unlisted: int
    dropped_samples: int
    clock: dict[str, Any] | None
    streams: list[dict[str, Any]]
    checks: list[dict[str, Any]]
    out_of_range: int
    read_options: dict[str, Any]
    def __len__(self) -> int: ...
    def channel(self, name: str) -> Channel: ...
    @property
    def units(self) -> dict[str, str]: ...
    @property
    def temperature(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def duration(self) -> float | None: ...
    def to_pandas(self) -> Any: ...

PathLike = Union[str, "os.PathLike[str]"]
Units = Union[dict[str, str], Sequence[str], str, None]

def read(
    path: PathLike,
    rate: float | None = None,
    units: Units = None,
    topic: str | None = None,
    instance: int | None = None,
    temp_topic: str | None = None,
) -> Recording: ...
def simulate(
    preset: Literal["mpu9250-thesis", "white"] | str = "mpu9250-thesis",
    duration: float | None = None,
    rate: float | None = None,
    profile: str | None = None,
    seed: int | None = None,
) -> Recording: ...

Firmware = Literal["px4", "ardupilot"]
Runs = Union[PathLike, Recording, Sequence[Union[PathLike, Recording]]]

class TcalModel:
    name: str | None
    warnings: list[str]
    export_warnings: list[str]
    def __init__(self, text: str, name: str | None = None, warnings: Sequence[str] = ()) -> None: ...
    @classmethod
    def load(cls, path: PathLike) -> TcalModel: ...
    def to_json(self) -> str: ...
    def save(self, path: PathLike) -> None: ...
    @property
    def t_ref(self) -> float: ...
    @property
    def t_min(self) -> float: ...
    @property
    def t_max(self) -> float: ...
    @property
    def channels(self) -> dict[str, dict[str, Any]]: ...
    def apply(self, recording: Recording) -> Recording: ...
    def evaluate(
        self,
        runs: Runs,
        export: Firmware | None = None,
        params: PathLike | None = None,
        rate: float | None = None,
        units: Units = None,
        topic: str | None = None,
        instance: int | None = None,
        temp_topic: str | None = None,
    ) -> dict[str, Any]: ...
    def export(self, firmware: Firmware, instance: int | None = None, device_id: int | None = None) -> str: ...

def tcal_fit(
    runs: Runs,
    channels: Sequence[str] | str | None = None,
    order: int | Literal["auto"] = "auto",
    tref: float | None = None,
    bin_width: float = 1.0,
    rate_term: bool = False,
    firmware: Firmware | None = None,
    rate: float | None = None,
    units: Units = None,
    topic: str | None = None,
    instance: int | None = None,
    temp_topic: str | None = None,
) -> TcalModel: ...
