// Cards: what the tablet shows for a reply, drawn here from the data the app sends.
// Nothing is loaded from elsewhere; the original address is shown as text only.
"use strict";

const SVG = "http://www.w3.org/2000/svg";

function el(tag, attrs, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) node.setAttribute(k, v);
  for (const c of children) node.append(c instanceof Node ? c : String(c));
  return node;
}

function svg(tag, attrs) {
  const node = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs || {})) node.setAttribute(k, v);
  return node;
}

function clockFace(card) {
  const face = svg("svg", {viewBox: "0 0 200 200", width: 180, height: 180, class: "clock"});
  face.append(svg("circle", {cx: 100, cy: 100, r: 95, class: "dial"}));
  for (let i = 0; i < 12; i++) {
    const a = i * Math.PI / 6;
    face.append(svg("line", {x1: 100 + 80 * Math.sin(a), y1: 100 - 80 * Math.cos(a),
      x2: 100 + 90 * Math.sin(a), y2: 100 - 90 * Math.cos(a), class: "tick"}));
  }
  const hand = (turns, length, cls) => {
    const a = turns * 2 * Math.PI;
    face.append(svg("line", {x1: 100, y1: 100, x2: 100 + length * Math.sin(a),
      y2: 100 - length * Math.cos(a), class: cls}));
  };
  hand(((card.hour % 12) + card.minute / 60) / 12, 50, "hand hour");
  hand((card.minute + card.second / 60) / 60, 75, "hand minute");
  face.append(svg("circle", {cx: 100, cy: 100, r: 4, class: "pin"}));
  return el("div", {class: "clock-card"}, face,
    el("div", {}, el("p", {class: "big", id: "card-title"}, card.city),
      el("p", {class: "big"}, card.time), el("p", {class: "meta"}, card.date + " · " + card.zone)));
}

const WEATHER_ICONS = [[/thunder|storm/, "⛈"], [/snow/, "❄"], [/rain|drizzle|shower/, "🌧"],
  [/fog|mist/, "🌫"], [/cloud|overcast|grey/, "☁"], [/sun|clear|bright|fine/, "☀"]];

function weatherCard(card) {
  const days = card.days.map(d => {
    const icon = (WEATHER_ICONS.find(([re]) => re.test(d.condition)) || [0, "🌡"])[1];
    const extra = [];
    if (d.low_c !== undefined && d.high_c !== undefined) extra.push(`${d.low_c}–${d.high_c} °C`);
    if (d.rain_chance !== undefined) extra.push(`rain ${d.rain_chance} %`);
    if (d.wind_kmh !== undefined) extra.push(`wind ${d.wind_kmh} km/h`);
    if (d.humidity !== undefined) extra.push(`humidity ${d.humidity} %`);
    return el("li", {class: d.current ? "current day" : "day"},
      el("span", {class: "icon"}, icon), el("b", {}, d.day), " ",
      el("span", {class: "big"}, `${d.temp_c} °C`), " ", d.condition,
      el("div", {class: "meta"}, extra.join(" · ")));
  });
  return el("div", {}, el("p", {class: "big", id: "card-title"}, card.city),
    el("ul", {class: "days"}, ...days));
}

function newsCard(card) {
  return el("div", {}, el("p", {class: "big", id: "card-title"}, "News"),
    el("ul", {class: "news"}, ...card.items.map(n => el("li", {class: n.current ? "current" : ""},
      el("b", {}, n.title), n.category ? el("span", {class: "tag"}, n.category) : "",
      el("div", {class: "meta"}, n.summary)))));
}

function knowledgeCard(card) {
  return el("div", {}, el("p", {class: "big", id: "card-title"}, card.title),
    el("p", {}, card.summary),
    el("p", {class: "related"}, "Related: ",
      ...card.related.map(r => el("span", {class: "tag"}, r))));
}

function imageCard(card) {
  return el("div", {}, el("p", {class: "big", id: "card-title"}, card.title || ""),
    el("img", {src: card.src, alt: card.kind === "photo" ? "the photo" : "the map",
      class: "shown"}));
}

function placeCard(card) {
  const map = svg("svg", {viewBox: "-180 -90 360 180", width: 360, height: 180, class: "world"});
  map.append(svg("rect", {x: -180, y: -90, width: 360, height: 180, class: "sea"}));
  for (let lon = -150; lon <= 150; lon += 30) {
    map.append(svg("line", {x1: lon, y1: -90, x2: lon, y2: 90, class: "grid"}));
  }
  for (let lat = -60; lat <= 60; lat += 30) {
    map.append(svg("line", {x1: -180, y1: lat, x2: 180, y2: lat, class: "grid"}));
  }
  map.append(svg("circle", {cx: card.lon, cy: -card.lat, r: 5, class: "spot"}));
  return el("div", {}, el("p", {class: "big", id: "card-title"}, card.title || "Here"), map,
    el("p", {class: "meta"}, `${card.lat.toFixed(2)}°, ${card.lon.toFixed(2)}°`));
}

function songCard(card) {
  return el("div", {}, el("p", {class: "big", id: "card-title"}, "🎵 " + card.title),
    el("p", {class: "meta"}, "I sing and dance it for you."));
}

const CARDS = {clock: clockFace, weather: weatherCard, news: newsCard,
  knowledge: knowledgeCard, image: imageCard, place: placeCard, song: songCard};

// Fill `box` with the card of a reply (or empty it when there is none).
function renderCard(box, card) {
  box.replaceChildren();
  box.dataset.kind = card ? card.kind : "none";
  if (!card) return;
  const draw = CARDS[card.kind];
  if (draw) box.append(draw(card));
  if (card.link) box.append(el("p", {class: "link meta"}, "Original: ", el("code", {}, card.link)));
}
