"""What each person of a household likes: preferences learnt from feedback (issue: feedback)."""
