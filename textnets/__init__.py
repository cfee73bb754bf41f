"""Text networks shared by style transfer and VQG: vocabulary, batches, generator, TextCNN, loop."""
