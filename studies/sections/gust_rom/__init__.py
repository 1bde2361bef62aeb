"""The gust_rom section of a study."""
