import os
from typing import Any, Literal, Sequence, TypedDict, Union

import numpy as np
import numpy.typing as npt

from . import allantools as allantools

__all__ = ["__version__", "allantools", "Channel", "Curve", "ImuthermError", "Recording", "STATISTICS",
           "analyze", "noise_terms", "read", "simulate", "TcalModel", "tcal_fit", "adev", "oadev", "mdev",
           "tdev", "hdev", "ohdev", "totdev", "mtotdev", "ttotdev", "htotdev", "theo1"]

__version__: str

class ImuthermError(ValueError): ...

STATISTICS: tuple[str, ...]

_Taus = Union[Literal["octave", "decade", "all", "many"], Sequence[float], npt.NDArray[np.floating]]
_DataType = Literal["freq", "phase"]
_Samples = npt.ArrayLike

class Curve:
    def __init__(self, fields: dict[str, Any]) -> None: ...
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
    y: _Samples,
    rate: float = 1.0,
    taus: _Taus = "octave",
    data_type: _DataType = "freq",
    confidence: float = 0.683,
) -> Curve: ...
def adev(y: _Samples, rate: float = 1.0, taus: _Taus = "octave", data_type: _DataType = "freq", confidence: float = 0.683) -> Curve: ...
def oadev(y: _Samples, rate: float = 1.0, taus: _Taus = "octave", data_type: _DataType = "freq", confidence: float = 0.683) -> Curve: ...
def mdev(y: _Samples, rate: float = 1.0, taus: _Taus = "octave", data_type: _DataType = "freq", confidence: float = 0.683) -> Curve: ...
def tdev(y: _Samples, rate: float = 1.0, taus: _Taus = "octave", data_type: _DataType = "freq", confidence: float = 0.683) -> Curve: ...
def hdev(y: _Samples, rate: float = 1.0, taus: _Taus = "octave", data_type: _DataType = "freq", confidence: float = 0.683) -> Curve: ...
def ohdev(y: _Samples, rate: float = 1.0, taus: _Taus = "octave", data_type: _DataType = "freq", confidence: float = 0.683) -> Curve: ...
def totdev(y: _Samples, rate: float = 1.0, taus: _Taus = "octave", data_type: _DataType = "freq", confidence: float = 0.683) -> Curve: ...
def mtotdev(y: _Samples, rate: float = 1.0, taus: _Taus = "octave", data_type: _DataType = "freq", confidence: float = 0.683) -> Curve: ...
def ttotdev(y: _Samples, rate: float = 1.0, taus: _Taus = "octave", data_type: _DataType = "freq", confidence: float = 0.683) -> Curve: ...
def htotdev(y: _Samples, rate: float = 1.0, taus: _Taus = "octave", data_type: _DataType = "freq", confidence: float = 0.683) -> Curve: ...
def theo1(y: _Samples, rate: float = 1.0, taus: _Taus = "octave", data_type: _DataType = "freq", confidence: float = 0.683) -> Curve: ...

class _TermEstimate(TypedDict, total=False):
    value: float | None
    lo: float
    hi: float
    reason: str

class _TermReading(TypedDict):
    symbol: str
    slope: _TermEstimate
    fit: _TermEstimate
    bound: float | None
    kept: bool
    value: float | None
    how: Literal["fit", "slope", "upper_bound", "none"]
    note: str | None

class _Interval(TypedDict):
    value: float
    lo: float
    hi: float
    unit: str

class _GaussMarkov(TypedDict):
    sigma: _Interval
    tau_c: _Interval

class _Candidate(TypedDict):
    label: str
    criterion: float
    chi2: float
    parameters: int

class _Model(TypedDict):
    label: str
    fits: bool
    chi2: float | None
    dof: int | None
    chi2_reduced: float | None
    p_value: float | None
    criterion: float | None
    points: int
    left_out_taus: list[float]
    outside_taus: list[float]
    evidence: list[list[Any]]
    candidates: list[_Candidate]
    gauss_markov: list[_GaussMarkov]
    bounds: list[list[Any]]
    defeat: _Defeat | None

class _Defeat(TypedDict):
    candidate: str
    process: str | None
    tau: float
    ratio: float
    sigmas: float | None
    text: str

class _StateSpaceTerm(TypedDict):
    kind: str
    tau_c_s: float | None
    q_c: float | None
    sigma: float | None
    note: str

class _FilterParam(TypedDict):
    name: str
    value: float
    unit: str
    formula: str
    source: str

class _FilterParams(TypedDict):
    filter: Literal["px4_ekf2", "ardupilot_ekf3"]
    dt_s: float
    params: list[_FilterParam]
    left_out: list[str]

class _NoiseTerms(TypedDict):
    curve: dict[str, Any]
    terms: dict[str, _TermReading]
    model: _Model
    verdict: Literal["fits", "does_not_fit", "no_candidate_fits"]
    state_space: list[_StateSpaceTerm]
    filters: list[_FilterParams] | None
    kalibr: list[_FilterParam] | None

def noise_terms(y: _Samples, rate: float = 1.0, confidence: float = 0.95,
                quantity: Literal["angular_rate", "acceleration"] | None = None) -> _NoiseTerms: ...

class Channel:
    def __init__(self, fields: dict[str, Any]) -> None: ...
    name: str
    source: str
    quantity: str
    unit: str
    unit_source: str
    data: npt.NDArray[np.float64]

class _Problem(TypedDict):
    kind: str
    line: int | None
    column: int | None
    channel: str | None
    count: int
    message: str

class Recording:
    def __init__(self, fields: dict[str, Any]) -> None: ...
    channels: dict[str, npt.NDArray[np.float64]]
    rate: float | None
    rate_source: str
    timestamps: npt.NDArray[np.float64] | None
    timestamp_slots: npt.NDArray[np.int64] | None
    metadata: dict[str, Any]
    file: str | None
    format: str
    lines: int | None
    notes: list[str]
    problems: list[_Problem]
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

_PathLike = Union[str, "os.PathLike[str]"]
_Units = Union[dict[str, str], Sequence[str], str, None]

def read(
    path: _PathLike,
    rate: float | None = None,
    units: _Units = None,
    topic: str | None = None,
    instance: int | None = None,
    temp_topic: str | None = None,
    allow_partial: bool = False,
) -> Recording: ...
def simulate(
    preset: Literal["mpu9250-thesis", "white"] | str = "mpu9250-thesis",
    duration: float | None = None,
    rate: float | None = None,
    profile: str | None = None,
    seed: int | None = None,
    unit: str | None = None,
    scatter: str | None = None,
    defect: str | None = None,
) -> Recording: ...

_Firmware = Literal["px4", "ardupilot"]
_Runs = Union[_PathLike, Recording, Sequence[Union[_PathLike, Recording]]]

class TcalModel:
    name: str | None
    warnings: list[str]
    export_warnings: list[str]
    def __init__(self, text: str, name: str | None = None, warnings: Sequence[str] = ()) -> None: ...
    @classmethod
    def load(cls, path: _PathLike) -> TcalModel: ...
    def to_json(self) -> str: ...
    def save(self, path: _PathLike) -> None: ...
    @property
    def t_ref(self) -> float: ...
    @property
    def t_min(self) -> float: ...
    @property
    def t_max(self) -> float: ...
    @property
    def channels(self) -> dict[str, dict[str, Any]]: ...
    @property
    def instance(self) -> int | None: ...
    @property
    def instances(self) -> dict[int, TcalModel]: ...
    def apply(self, recording: Recording, instance: int | None = None) -> Recording: ...
    def evaluate(
        self,
        runs: _Runs,
        export: _Firmware | None = None,
        params: _PathLike | None = None,
        rate: float | None = None,
        units: _Units = None,
        topic: str | None = None,
        instance: int | Literal["all"] | None = None,
        temp_topic: str | None = None,
    ) -> dict[str, Any]: ...
    def export(self, firmware: _Firmware, instance: int | None = None, device_id: int | None = None) -> str: ...

def tcal_fit(
    runs: _Runs,
    channels: Sequence[str] | str | None = None,
    order: int | Literal["auto"] = "auto",
    tref: float | None = None,
    bin_width: float = 1.0,
    rate_term: bool = False,
    firmware: _Firmware | None = None,
    rate: float | None = None,
    units: _Units = None,
    topic: str | None = None,
    instance: int | Literal["all"] | None = None,
    temp_topic: str | None = None,
) -> TcalModel: ...
