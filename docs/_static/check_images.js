// Marks the page with the number of images that failed to load (read by the
// site's browser test: tests/unit/test_docs_site.py).
window.addEventListener("load", function () {
  var broken = 0;
  var images = document.images;
  for (var k = 0; k < images.length; k++) {
    if (!images[k].complete || images[k].naturalWidth === 0) {
      broken += 1;
    }
  }
  document.body.setAttribute("data-images", String(images.length));
  document.body.setAttribute("data-broken-images", String(broken));
});
