"""The weather forecast the robot's weather service hands it: days by city. A household
scenario carries one (its ``weather`` block), a real robot would fetch one; the dialogue's
weather answers read it (dialogue/qa/weather.py)."""

from __future__ import annotations

from pydantic import Field

from core.config_files import StrictModel


class WeatherDay(StrictModel):
    """One day's weather in one city (answers the dialogue's weather questions)."""

    condition: str = Field(min_length=1)
    temp_c: float
    low_c: float | None = None
    high_c: float | None = None
    rain_chance: float | None = Field(default=None, ge=0, le=100)
    wind_kmh: float | None = Field(default=None, ge=0)
    humidity: float | None = Field(default=None, ge=0, le=100)


class Weather(StrictModel):
    """A forecast: days by city."""

    home: str | None = None
    source: str | None = None
    cities: dict[str, dict[str, WeatherDay]] = Field(min_length=1)
