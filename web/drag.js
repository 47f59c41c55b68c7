// A drag that began with the pointer event `down` on `el`: `move(e)` for every move until the
// button is released. The pointer is captured, so the drag goes on outside the element; `el`
// has the class "dragging" meanwhile (the image's cursor shows it).
export function drag(el, down, move, end = () => {}) {
  el.setPointerCapture(down.pointerId);
  el.classList.add('dragging');
  const up = (e) => {
    el.classList.remove('dragging');
    el.removeEventListener('pointermove', move);
    el.removeEventListener('pointerup', up);
    end(e);
  };
  el.addEventListener('pointermove', move);
  el.addEventListener('pointerup', up);
}
