"""The offline QA bot: the eight question categories of thesis Table 3.4."""

CATEGORIES = ("information", "weather", "time", "news", "related_topics", "map", "music",
              "photo")
